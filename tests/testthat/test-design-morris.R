test_that("Morris screening ranks influential parameters above negligible ones", {
  skip_if_not_installed("sensitivity")
  sim <- bem_simulator(shipped_epw(2013))
  m <- screen_morris(sim, r = 10, seed = 1)
  expect_s3_class(m, "bayesbem_morris")
  expect_named(m, c("parameter", "mu_star", "mu", "sigma", "rank"))
  expect_equal(m$rank, 1:14)
  rank_of <- function(p) m$rank[m$parameter == p]
  for (strong in c("equipment_power_density", "lighting_power_density", "fan_total_efficiency")) {
    for (weak in c("wall_density_multiplier", "roof_density_multiplier")) {
      expect_lt(rank_of(strong), rank_of(weak))
    }
  }
  expect_lt(m$mu_star[m$parameter == "roof_density_multiplier"], 0.01)
  expect_identical(screen_morris(sim, r = 10, seed = 1), m)
})

test_that("Morris screening of two meters ranks each on its own output", {
  skip_if_not_installed("sensitivity")
  sim <- bem_simulator(shipped_epw(2013), output = c("electricity", "gas"))
  params <- bem_parameters()[c(2, 4, 5), ]
  m <- screen_morris(sim, params, r = 5, seed = 3)
  expect_named(m, c("output", "parameter", "mu_star", "mu", "sigma", "rank"))
  for (k in c("electricity", "gas")) {
    alone <- screen_morris(bem_simulator(shipped_epw(2013), output = k), params, r = 5, seed = 3)
    expect_equal(as.data.frame(m[m$output == k, -1]), as.data.frame(alone), ignore_attr = TRUE)
  }
  # the heating set point ranks first for gas, not for electricity
  expect_equal(m$parameter[m$output == "gas" & m$rank == 1], "heating_setpoint")
  expect_error(plot_morris(m), "2 outputs", class = "bayesbem_error_argument")
  expect_s3_class(plot_morris(m[m$output == "gas", ]), "ggplot")
})

test_that("Morris screening per period gives effects for every period", {
  skip_if_not_installed("sensitivity")
  sim <- bem_simulator(shipped_epw(2013))
  params <- bem_parameters()[c(1, 12, 13), ]
  m <- screen_morris(sim, params, r = 4, seed = 2, effects_on = "period")
  expect_equal(nrow(m), 3 * 12)
  cooling <- m[m$parameter == "cooling_setpoint", ]
  # the cooling set point matters in summer, not in winter
  expect_gt(cooling$mu_star[cooling$period == 7], cooling$mu_star[cooling$period == 1])
  expect_error(plot_morris(m), class = "bayesbem_error_argument")
})
