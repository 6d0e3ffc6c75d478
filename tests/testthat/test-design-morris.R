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

test_that("Morris screening per period gives effects for every period", {
  skip_if_not_installed("sensitivity")
  sim <- bem_simulator(shipped_epw(2013))
  params <- bem_parameters()[c(1, 12, 13), ]
  m <- screen_morris(sim, params, r = 4, seed = 2, output = "period")
  expect_equal(nrow(m), 3 * 12)
  cooling <- m[m$parameter == "cooling_setpoint", ]
  # the cooling set point matters in summer, not in winter
  expect_gt(cooling$mu_star[cooling$period == 7], cooling$mu_star[cooling$period == 1])
  expect_error(plot_morris(m), class = "bayesbem_error_argument")
})

test_that("plot_morris() draws mu* against sigma", {
  skip_if_not_installed("sensitivity")
  sim <- bem_simulator(shipped_epw(2013))
  m <- screen_morris(sim, r = 5, seed = 3)
  d <- plot_morris_data(m)
  expect_named(d, c("parameter", "mu_star", "sigma", "rank"))
  p <- plot_morris(m)
  expect_s3_class(p, "ggplot")
  skip_if_not_installed("vdiffr")
  vdiffr::expect_doppelganger("morris", p)
})

test_that("screen_morris() takes the old argument name params with a deprecation warning", {
  skip_if_not_installed("sensitivity")
  withr::local_options(lifecycle_verbosity = "warning")
  sim <- bem_simulator(shipped_epw(2013))
  expect_warning(old <- screen_morris(sim, params = bem_parameters()[c(3, 12), ], r = 2, seed = 1),
                 class = "lifecycle_warning_deprecated")
  expect_equal(old, screen_morris(sim, bem_parameters()[c(3, 12), ], r = 2, seed = 1))
})
