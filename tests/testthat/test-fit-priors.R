test_that("koh_priors() defaults are the paper's", {
  p <- koh_priors()
  expect_equal(p$rho_eta, c(1, 0.3))
  expect_equal(p$rho_delta, c(1, 0.3))
  expect_equal(p$lambda_eta, c(10, 10))
  expect_equal(p$lambda_delta, c(10, 0.3))
  expect_equal(p$lambda_e, c(10, 0.03))
  expect_length(p$tf, 0)
})

test_that("prior means in physical units map to the [0, 1] scale", {
  d <- koh_data(seb_field, seb_sim)
  mu <- c(equipment_power_density = 21.9, fan_total_efficiency = 0.5)
  sd <- bayesbem:::koh_stan_data(d, koh_priors(tf = prior_strength("weak", mu)))
  lo <- min(seb_sim$equipment_power_density)
  hi <- max(seb_sim$equipment_power_density)
  expect_equal(sd$tf_mu[2], (21.9 - lo) / (hi - lo))
  expect_equal(sd$tf_mu[1], (0.5 - min(seb_sim$fan_total_efficiency)) /
                 diff(range(seb_sim$fan_total_efficiency)))
  expect_equal(as.vector(sd$tf_is_normal), c(1, 1, 0))
  expect_equal(as.vector(sd$tf_sd[1:2]), c(0.2, 0.2))
})

test_that("the scaled set centres the emulator's variance on what its mean leaves", {
  d <- koh_data(seb_field, seb_sim)
  rate <- function(...) bayesbem:::koh_stan_data(d, koh_priors(...))$lambda_eta_rate
  # independently: the runs (standardised by their own mean and sd) less
  # their least-squares plane in the scaled inputs and parameters
  runs <- seb_sim
  # fan efficiency is on the reciprocal scale (koh_data(scales = "auto"))
  runs$fan_total_efficiency <- -1 / runs$fan_total_efficiency
  eta <- (runs$eta - mean(runs$eta)) / stats::sd(runs$eta)
  inputs <- c("temp", "rh", "solar", "equipment_power_density", "fan_total_efficiency",
              "infiltration_per_exterior_area")
  scaled <- lapply(inputs, function(v) {
    all <- c(runs[[v]], if (v %in% names(seb_field)) seb_field[[v]])
    (runs[[v]] - min(all)) / diff(range(all))
  })
  plane <- stats::lm(eta ~ ., data = stats::setNames(as.data.frame(scaled), inputs))
  v <- sum(stats::residuals(plane)^2) / (nrow(runs) - 1)
  expect_equal(rate(set = "scaled"), 10 * v, tolerance = 1e-10)
  expect_lt(v, 0.5)
  # the paper's set, and any mean that leaves the runs' whole variance
  expect_equal(rate(), 10)
  expect_equal(rate(set = "scaled", emulator_mean = "zero"), 10)
  expect_equal(rate(set = "scaled", emulator_mean = "constant", lambda_eta = c(10, 4)), 4)
  expect_error(koh_priors(set = "wide"), class = "bayesbem_error_argument")
})

test_that("prior_strength() gives the paper's three levels", {
  mu <- c(equipment_power_density = 21.9)
  expect_equal(prior_strength("flat", mu)$equipment_power_density$family, "uniform")
  expect_equal(prior_strength("weak", mu)$equipment_power_density$sd, 0.2)
  expect_equal(prior_strength("specific", mu)$equipment_power_density$sd, 0.05)
  expect_equal(prior_strength("specific", mu)$equipment_power_density$mu, 21.9)
})

test_that("bad priors get classed errors", {
  expect_error(prior_normal(1, 0), class = "bayesbem_error_prior")
  expect_snapshot(prior_normal(1, -0.2), error = TRUE)
  expect_snapshot(koh_priors(lambda_e = c(10, -1)), error = TRUE)
  expect_snapshot(koh_priors(tf = list(prior_normal(1, 0.2))), error = TRUE)
  d <- koh_data(seb_field, seb_sim)
  out_of_range <- koh_priors(tf = prior_strength("weak", c(equipment_power_density = 45)))
  expect_error(bayesbem:::koh_stan_data(d, out_of_range), class = "bayesbem_error_prior")
  expect_snapshot(bayesbem:::koh_stan_data(d, out_of_range), error = TRUE)
  unknown <- koh_priors(tf = prior_strength("weak", c(lighting = 10)))
  expect_snapshot(bayesbem:::koh_stan_data(d, unknown), error = TRUE)
  expect_snapshot(prior_strength("weak"), error = TRUE)
})
