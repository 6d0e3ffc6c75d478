# Fits in tests draw no progress bar (it would interleave with the reporter).
options(bayesbem.progress = FALSE)

# One small seeded fit of the case study, made once per test run and shared
# by every test that needs a fitted model, at adapt_delta 0.9 (the tests'
# expectations were set on it; the dense program is slow at 0.99). Three
# field months are also predicted inside Stan (the paper's Appendix D) to
# compare the two routes.
shared_predict_at <- function() seb_field[c(1, 6, 11), c("temp", "rh", "solar")]

shared_fit <- local({
  fit <- NULL
  function() {
    if (is.null(fit)) {
      fit <<- suppressWarnings(
        calibrate(seb_field, seb_sim, chains = 2, iter = 1000, seed = 20180601, cores = 2,
                  control = list(adapt_delta = 0.9), refresh = 0,
                  predict_at = shared_predict_at()),
        classes = "bayesbem_warning_convergence")
    }
    fit
  }
})
