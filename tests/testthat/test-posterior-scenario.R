test_that("scenario() takes changes of the simulator's parameters, within their ranges", {
  sim <- linear_seb_simulator()
  s <- scenario(sim, set = c(lighting_power_density = 8),
                scale = list(equipment_power_density = 0.7))
  expect_s3_class(s, "bayesbem_scenario")
  expect_equal(s$set, c(lighting_power_density = 8))
  expect_equal(s$scale, c(equipment_power_density = 0.7))
  expect_match(s$name, "lighting_power_density = 8, equipment_power_density x 0.7")
  expect_equal(scenario(sim)$name, "as calibrated")
  expect_output(print(s), "bayesbem_scenario")
  expect_snapshot(scenario(sim, scale = c(equipment_power_densty = 0.7)), error = TRUE)
  expect_snapshot(scenario(sim, set = c(lighting_power_density = 100)), error = TRUE)
  expect_error(scenario(sim, set = c(lighting_power_density = 8),
                        scale = c(lighting_power_density = 2)),
               class = "bayesbem_error_scenario")
  expect_error(scenario(sim, scale = c(equipment_power_density = -1)),
               class = "bayesbem_error_scenario")
  expect_error(scenario(sim, scale = c(equipment_power_density = "0.7")),
               class = "bayesbem_error_scenario")
  expect_error(scenario(seb_sim), class = "bayesbem_error_argument")
})

test_that("a scenario's simulated draws equal the simulator at the posterior draws", {
  sim <- linear_seb_simulator()
  withr::local_seed(1)
  s <- scenario(sim, scale = c(equipment_power_density = 0.7),
                set = c(lighting_power_density = 8))
  p <- predict_scenario(seb_fit, s, ndraws = 20, discrepancy = "none", noise = FALSE)
  d <- used_draws(seb_fit, p$draw)
  by_hand <- outer(1000 + 40 * 0.7 * d$equipment_power_density - 300 * d$fan_total_efficiency +
                     2e5 * d$infiltration_per_exterior_area + 80,
                   5 * abs(seb_field$temp - 15), `+`)
  expect_equal(unname(p$simulated), unname(by_hand), tolerance = 1e-6)
  expect_equal(p$y, p$simulated)
  expect_equal(length(p$draw), 20)
  # the summary has a row per period and the total
  sm <- summary(p)
  expect_equal(sm$period, c(as.character(1:12), "total"))
  expect_equal(sm$mean[13], mean(rowSums(p$y)))
  expect_output(print(p), "bayesbem_scenario_prediction")
})

test_that("a scenario's checks say what is wrong", {
  sim <- linear_seb_simulator()
  # scaled draw by draw beyond the parameter's range
  expect_snapshot(predict_scenario(seb_fit, scenario(sim, scale = c(equipment_power_density = 0.1)),
                                   ndraws = 5),
                  error = TRUE)
  other <- simulator(function(params, x) x$temp, x = seb_field["temp"],
                     parameters = bem_parameters())
  expect_error(predict_scenario(seb_fit, other, ndraws = 5), class = "bayesbem_error_simulator")
  expect_error(predict_scenario(seb_fit, "sim"), class = "bayesbem_error_argument")
  expect_error(predict_scenario(seb_fit, sim, ndraws = 5, nosie = FALSE), class = "rlib_error_dots_nonempty")
  failing <- simulator(function(params, x) stop("the weather file is missing"),
                       x = seb_field[c("temp", "rh", "solar")], parameters = bem_parameters())
  expect_snapshot(suppressWarnings(predict_scenario(seb_fit, failing, ndraws = 2)), error = TRUE)
})

test_that("at the training weather the simulator route agrees with predict()", {
  skip_on_cran()
  case <- linear_case()
  withr::local_seed(3)
  route <- predict_scenario(case$fit, case$sim, ndraws = 400, noise = FALSE)$y
  emulator <- predict(case$fit, ndraws = 400, summary = FALSE)
  # an exact emulator: the means agree within Monte Carlo error ...
  se <- sqrt(apply(route, 2, stats::var) / 400 + apply(emulator, 2, stats::var) / 400)
  expect_lt(max(abs(colMeans(route) - colMeans(emulator)) / se), 4)
  # ... and so do the spreads
  ratio <- apply(route, 2, stats::sd) / apply(emulator, 2, stats::sd)
  expect_true(all(ratio > 0.75 & ratio < 1.33))
})

test_that("the discrepancy at the simulator's output is the Gaussian conditional", {
  # a joint normal whose delta given eta is known in closed form
  cov <- matrix(c(2, 0.3, -0.8, 0.1,
                  0.3, 1.5, 0.2, -0.6,
                  -0.8, 0.2, 1.2, 0.3,
                  0.1, -0.6, 0.3, 1.1), 4)
  mean <- c(1, 2, 0.5, -0.5)
  s <- c(1.5, 1.2)
  gain <- cov[3:4, 1:2] %*% solve(cov[1:2, 1:2])
  m <- drop(mean[3:4] + gain %*% (s - mean[1:2]))
  v <- cov[3:4, 3:4] - gain %*% cov[1:2, 3:4]
  withr::local_seed(2)
  draws <- t(replicate(20000, delta_given_eta(list(mean = mean, cov = cov), s)))
  # Monte Carlo error of 20000 draws: about 0.007 for the means
  expect_lt(max(abs(colMeans(draws) - m)), 0.03)
  expect_lt(max(abs(stats::cov(draws) - v)), 0.03)
})

test_that("a proportional discrepancy is the calibrated model's, scaled by the scenario's use", {
  sim <- linear_seb_simulator()
  retrofit <- scenario(sim, scale = c(equipment_power_density = 0.7))
  withr::local_seed(6)
  calibrated <- predict_scenario(seb_fit, sim, ndraws = 20, noise = FALSE)
  withr::local_seed(6)
  same <- predict_scenario(seb_fit, retrofit, ndraws = 20, noise = FALSE)
  withr::local_seed(6)
  scaled <- predict_scenario(seb_fit, retrofit, ndraws = 20, discrepancy = "proportional",
                             noise = FALSE)
  expect_identical(scaled$simulated, same$simulated)
  expect_equal(scaled$delta, calibrated$delta * scaled$simulated / calibrated$simulated)
  # without a change, proportional is the same discrepancy
  withr::local_seed(6)
  expect_equal(predict_scenario(seb_fit, sim, ndraws = 20, discrepancy = "proportional",
                                noise = FALSE)$delta, calibrated$delta)
  none <- predict_scenario(seb_fit, retrofit, ndraws = 20, discrepancy = "none", noise = FALSE)
  expect_equal(none$y, none$simulated)
  expect_output(print(scaled), "the discrepancy \\(proportional\\)")
  expect_error(predict_scenario(seb_fit, retrofit, discrepancy = TRUE),
               class = "bayesbem_error_argument")
})
