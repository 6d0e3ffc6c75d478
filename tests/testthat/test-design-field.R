test_that("simulate_field() adds the effect and the noise to the truth", {
  sim <- bem_simulator(shipped_epw(2013))
  clean <- simulate_field(sim, list(equipment_power_density = 15))
  run <- simulate_design(sim, data.frame(equipment_power_density = 15))
  expect_equal(clean$y, run$eta)
  expect_named(clean, c("y", "temp", "rh", "solar"))
  cov <- data.frame(flag = rep(0:1, 6))
  noisy <- simulate_field(sim, list(equipment_power_density = 15), covariates = cov,
                          effect = function(d) 100 * d$flag + d$rh, noise_sd = 10, seed = 3)
  expect_named(noisy, c("y", "temp", "rh", "solar", "flag"))
  expect_equal(attr(noisy, "effect"), 100 * cov$flag + sim$x$rh)
  noise <- noisy$y - attr(noisy, "simulated") - attr(noisy, "effect")
  expect_equal(noise, withr::with_seed(3, rnorm(12, sd = 10)))
  expect_equal(attr(noisy, "truth")$equipment_power_density, 15)
  expect_identical(simulate_field(sim, list(equipment_power_density = 15), noise_sd = 10,
                                  seed = 3)$y,
                   simulate_field(sim, list(equipment_power_density = 15), noise_sd = 10,
                                  seed = 3)$y)
})

test_that("bad effects and covariates get classed errors", {
  sim <- bem_simulator(shipped_epw(2013))
  expect_error(simulate_field(sim, list(equipment_power_density = 15), effect = function(d) 1),
               class = "bayesbem_error_argument")
  expect_snapshot(simulate_field(sim, list(equipment_power_density = 15),
                                 effect = function(d) 1), error = TRUE)
  expect_error(simulate_field(sim, list(equipment_power_density = 15),
                              covariates = data.frame(a = 1:3)),
               class = "bayesbem_error_covariates")
  expect_error(simulate_field(sim, list(equipment_power_density = 99)),
               class = "bayesbem_error_parameters")
  expect_error(simulate_field(sim, list(equipment_power_density = 15), noise_sd = -1),
               class = "bayesbem_error_argument")
})

test_that("simulate_field() of several outputs: the long table, each with its noise and effect", {
  sim <- two_output_simulator()
  truth <- list(equipment_power_density = 15)
  clean <- simulate_field(sim, truth)
  expect_named(clean, c("output", "y", "temp", "rh", "solar"))
  expect_equal(clean$output, rep(c("electricity", "gas"), each = 12))
  runs <- simulate_design(sim, data.frame(equipment_power_density = 15))
  expect_equal(clean$y, runs$eta)
  noisy <- simulate_field(sim, truth, effect = list(gas = function(d) 2 * d$rh),
                          noise_sd = c(electricity = 10, gas = 30), seed = 4)
  expect_equal(attr(noisy, "effect"), c(rep(0, 12), 2 * sim$x$rh))
  noise <- noisy$y - attr(noisy, "simulated") - attr(noisy, "effect")
  expected <- withr::with_seed(4, c(rnorm(12, sd = 10), rnorm(12, sd = 30)))
  expect_equal(noise, expected)
  expect_snapshot(simulate_field(sim, truth, effect = function(d) d$rh), error = TRUE)
  expect_snapshot(simulate_field(sim, truth, noise_sd = c(water = 1)), error = TRUE)
})
