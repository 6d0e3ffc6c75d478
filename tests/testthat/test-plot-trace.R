test_that("trace plots cover tf, the betas and the lambdas", {
  skip_on_cran()
  fit <- shared_fit()
  d <- plot_trace_data(fit)
  expect_setequal(as.character(unique(d$parameter)),
                  setdiff(posterior::variables(posterior::as_draws(fit)), "lp__"))
  expect_equal(nrow(d), (length(posterior::variables(posterior::as_draws(fit))) - 1) * 1000)
  expect_snapshot(plot_trace(fit, variables = "lambda_x"), error = TRUE)
})

test_that("plot_trace() draws the paper's Fig 7", {
  skip_if_not_installed("vdiffr")
  fit <- seb_fit
  d <- plot_trace_data(fit, variables = "lambda_e")
  expect_equal(d$value[d$chain == 2], as.vector(bayesbem:::stan_draws(fit, "lambda_e")[201:400]))
  vdiffr::expect_doppelganger(
    "trace",
    plot_trace(fit, variables = c("equipment_power_density", "beta_eta[temp]", "lambda_e"))
  )
})
