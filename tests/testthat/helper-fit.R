# Fits in tests draw no progress bar (it would interleave with the reporter).
options(bayesbem.progress = FALSE)

# One small seeded fit of the case study, made once per test run and shared
# by every test that needs a fitted model: joint (every hyperparameter
# sampled), at adapt_delta 0.9 (the tests' expectations were set on it).
shared_fit <- local({
  fit <- NULL
  function() {
    if (is.null(fit)) {
      fit <<- suppressWarnings(
        calibrate(seb_field, seb_sim, chains = 2, iter = 1000, seed = test_seed(20180601), cores = 2,
                  modular = FALSE, control = list(adapt_delta = 0.9), refresh = 0),
        classes = "bayesbem_warning_convergence")
    }
    fit
  }
})

# Three field months predicted inside Stan (the paper's Appendix D), to
# compare the two routes, by a fit on five of the case study's runs (the
# dense program that predicting inside Stan needs is cubic in the rows).
shared_predict_at <- function() seb_field[c(1, 6, 11), c("temp", "rh", "solar")]

sampled_fit <- local({
  fit <- NULL
  function() {
    if (is.null(fit)) {
      fit <<- suppressWarnings(
        calibrate(seb_field, seb_sim[1:60, ], chains = 2, iter = 1000, seed = test_seed(20180601),
                  cores = 2, control = list(adapt_delta = 0.9), refresh = 0,
                  predict_at = shared_predict_at()),
        classes = "bayesbem_warning_convergence")
    }
    fit
  }
})

# A fit on two outputs of the embedded model, electricity and gas, 12
# months of 2013 (gas without its August bill), two parameters; made once
# per test session.
two_output_fit <- local({
  fit <- NULL
  function() {
    if (is.null(fit)) {
      sim <- two_output_simulator()
      pars <- bem_parameters()
      pars <- pars[pars$parameter %in% c("equipment_power_density", "infiltration_per_exterior_area"), ]
      runs <- simulate_design(sim, design_lhs(pars, 12, seed = 1))
      field <- simulate_field(sim, list(equipment_power_density = 15,
                                        infiltration_per_exterior_area = 8e-4),
                              noise_sd = c(electricity = 20, gas = 20), seed = 2)
      field <- field[!(field$output == "gas" & seq_len(nrow(field)) == 20), ]
      fit <<- suppressWarnings(calibrate(field, runs, chains = 2, iter = 600, seed = test_seed(3),
                                         progress = FALSE))
    }
    fit
  }
})

# The embedded model's electricity and gas over the 12 months of 2013.
two_output_simulator <- function() {
  bem_simulator(shipped_epw(2013), output = c("electricity", "gas"))
}

# `sim` as a simulator that counts its runs in `counter$calls`.
counting_simulator <- function(counter, sim = two_output_simulator()) {
  counter$calls <- 0
  simulator(function(params, x) {
    counter$calls <- counter$calls + 1
    sim$fun(params, x)
  }, sim$x, sim$parameters)
}

# The columns of a posterior draws matrix as a plain matrix, as
# bayesbem:::stan_draws() gives them.
unname_draws <- function(d) {
  array(as.vector(d), dim(d), list(NULL, colnames(d)))
}

# A verb's table on two_output_fit() (`all`, checked to have a first column
# output naming both outputs) and on its electricity view (`own`), from the
# same random numbers.
on_both_outputs <- function(verb, seed, ...) {
  fit <- two_output_fit()
  all <- withr::with_seed(seed, verb(fit, ...))
  testthat::expect_equal(unique(all$output), c("electricity", "gas"))
  own <- withr::with_seed(seed, verb(output_fit(fit, "electricity"), ...))
  list(fit = fit, all = all, own = own, electricity = all$output == "electricity")
}
