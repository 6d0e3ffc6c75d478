# One small seeded fit of the shipped case study, made once per test run and
# shared by every test that needs a fitted model.
shared_fit <- local({
  fit <- NULL
  function() {
    if (is.null(fit)) {
      fit <<- calibrate(seb_field, seb_sim, chains = 2, iter = 1000, seed = 20180601,
                        cores = 2, refresh = 0)
    }
    fit
  }
})
