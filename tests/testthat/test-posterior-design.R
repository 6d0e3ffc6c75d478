test_that("design_posterior() is a Latin hypercube over the posterior's central intervals", {
  d <- design_posterior(seb_fit, n = 10, level = 0.8, seed = 1)
  expect_named(d, seb_fit$data$names$t)
  expect_equal(nrow(d), 10)
  # on the emulator's [0, 1] scale: one run in each of the 10 strata
  # between the 10 % and 90 % posterior quantiles of every parameter
  tf <- bayesbem:::stan_draws(seb_fit, "tf")
  u <- bayesbem:::scale_t(d, seb_fit$data$scaling)
  for (k in seq_len(ncol(tf))) {
    q <- quantile(tf[, k], c(0.1, 0.9), names = FALSE)
    expect_equal(sort(floor((u[, k] - q[1]) / (q[2] - q[1]) * 10)), 0:9)
  }
  expect_identical(design_posterior(seb_fit, n = 10, level = 0.8, seed = 1), d)
})

test_that("design_posterior() runs bind to the fit's runs", {
  sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
  runs <- simulate_design(sim, design_posterior(seb_fit, n = 3, seed = 2))
  expect_equal(nrow(runs), 3 * nrow(sim$x))
  expect_setequal(names(runs), c(names(sim$x), seb_fit$data$names$t, "eta"))
})

test_that("design_posterior() rejects bad arguments with classed errors", {
  expect_snapshot(design_posterior(seb_fit, n = 1), error = TRUE)
  expect_error(design_posterior(seb_fit, n = "5"), class = "bayesbem_error_argument")
  expect_error(design_posterior(seb_fit, n = 5, level = 1.5), class = "bayesbem_error_argument")
  expect_error(design_posterior(seb_fit, n = 5, levle = 0.5), class = "rlang_error")
  expect_error(design_posterior(list(), n = 5), class = "bayesbem_error_argument")
})

test_that("a fit on several outputs gets one design of the parameters they share", {
  skip_on_cran()
  fit <- two_output_fit()
  expect_identical(design_posterior(fit, n = 6, seed = 2),
                   design_posterior(output_fit(fit, "gas"), n = 6, seed = 2))
})
