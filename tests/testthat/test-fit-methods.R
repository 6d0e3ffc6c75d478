test_that("print(), summary() and as_draws() show physical units and hyperparameters", {
  skip_on_cran()
  fit <- shared_fit()
  s <- summary(fit)
  expect_s3_class(s, "summary.bayesbem_fit")
  expect_named(s$parameters, c("variable", "mean", "sd", "q5", "q50", "q95",
                               "rhat", "ess_bulk", "ess_tail"))
  expect_equal(s$parameters$variable, c("fan_total_efficiency", "equipment_power_density",
                                        "infiltration_per_exterior_area"))
  expect_setequal(s$hyperparameters$variable,
                  c("beta_eta[temp]", "beta_eta[rh]", "beta_eta[solar]",
                    "beta_eta[fan_total_efficiency]", "beta_eta[equipment_power_density]",
                    "beta_eta[infiltration_per_exterior_area]",
                    "beta_delta[temp]", "beta_delta[rh]", "beta_delta[solar]",
                    "lambda_eta", "lambda_delta", "lambda_e",
                    "b[intercept]", "b[temp]", "b[rh]", "b[solar]", "b[fan_total_efficiency]",
                    "b[equipment_power_density]", "b[infiltration_per_exterior_area]"))
  out <- capture.output(print(fit))
  expect_true(any(grepl("Calibration parameters (physical units)", out, fixed = TRUE)))
  expect_true(any(grepl("equipment_power_density", out)))
  expect_true(any(grepl("lambda_e", out)))
  draws <- posterior::as_draws(fit)
  expect_s3_class(draws, "draws_array")
  expect_equal(posterior::ndraws(draws), 1000)
  tf <- bayesbem:::stan_draws(fit, "tf")[, 2]
  lo <- min(seb_sim$equipment_power_density)
  hi <- max(seb_sim$equipment_power_density)
  expect_equal(sort(as.vector(posterior::as_draws_matrix(draws)[, "equipment_power_density"])),
               sort(tf * (hi - lo) + lo))
})

test_that("methods reject arguments they do not use", {
  expect_error(summary(seb_fit, digits = 2), class = "rlib_error_dots_nonempty")
  expect_error(print(seb_fit, digits = 2), class = "rlib_error_dots_nonempty")
  expect_error(posterior::as_draws_df(seb_fit, n = 2), class = "rlib_error_dots_nonempty")
  expect_error(loo::loo(seb_fit, n_draws = 10), class = "rlib_error_dots_nonempty")
  expect_error(print(koh_priors(), 1), class = "rlib_error_dots_nonempty")
  expect_error(print(koh_data(seb_field, seb_sim), 1), class = "rlib_error_dots_nonempty")
  expect_error(print(check_convergence(seb_fit, warn = FALSE), colour = 2),
               class = "rlib_error_dots_nonempty")
})

test_that("summaries have the parameters as row names and print without scientific notation", {
  s <- summary(seb_fit)
  expect_equal(rownames(s$parameters), seb_fit$data$names$t)
  expect_equal(rownames(s$hyperparameters)[1], "beta_eta[temp]")
  out <- capture.output(print(seb_fit))
  expect_false(any(grepl("[0-9]e[-+][0-9]", out)))
  # each row to two significant digits of its sd
  epd <- s$parameters["equipment_power_density", ]
  line <- grep("^equipment_power_density ", out, value = TRUE)[1]
  expect_match(line, sprintf("^equipment_power_density +%.1f +%.1f ", epd$mean, epd$sd))
  inf <- s$parameters["infiltration_per_exterior_area", ]
  digits <- 2 - ceiling(log10(inf$sd))
  expect_match(grep("^infiltration_per_exterior_area ", out, value = TRUE)[1],
               formatC(inf$mean, format = "f", digits = digits), fixed = TRUE)
  expect_equal(bayesbem:::sd_decimals(c(1.2, 0.05, 0.00023, 400, 0, NA)), c(1, 3, 5, 0, 3, 3))
})
