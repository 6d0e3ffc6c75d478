test_that("scales = 'auto' puts fan efficiency on the reciprocal scale, the others as they are", {
  d <- koh_data(seb_field, seb_sim)
  expect_equal(d$scaling$t_scale,
               c(fan_total_efficiency = "reciprocal", equipment_power_density = "identity",
                 infiltration_per_exterior_area = "identity"))
  # independently: residual variance of the runs' linear fit on the inputs and
  # parameters, fan efficiency as it is and as 1 / efficiency
  rss <- function(f) sum(stats::residuals(stats::lm(f, data = seb_sim))^2)
  ratio <- rss(eta ~ temp + rh + solar + I(1 / fan_total_efficiency) + equipment_power_density +
                 infiltration_per_exterior_area) /
    rss(eta ~ temp + rh + solar + fan_total_efficiency + equipment_power_density +
          infiltration_per_exterior_area)
  expect_lt(ratio, 0.8)
  # tc is -1 / efficiency mapped to [0, 1], in the parameter's order
  v <- -1 / seb_sim$fan_total_efficiency
  expect_equal(unname(d$tc[, "fan_total_efficiency"]), (v - min(v)) / diff(range(v)))
  expect_equal(unname(bayesbem:::unscale_t(d$tc, d$scaling)), unname(as.matrix(seb_sim[5:7])),
               tolerance = 1e-12)
  bounds <- bayesbem:::t_bounds(d$scaling)
  expect_equal(unname(bounds$lower), unname(apply(seb_sim[5:7], 2, min)))
  expect_equal(unname(bounds$upper), unname(apply(seb_sim[5:7], 2, max)))
  expect_match(paste(capture.output(print(d)), collapse = "\n"),
               "fitted on the reciprocal scale: fan_total_efficiency", fixed = TRUE)
})

test_that("scales can be the paper's identity or given per parameter", {
  paper <- koh_data(seb_field, seb_sim, scales = "identity")
  expect_true(all(paper$scaling$t_scale == "identity"))
  expect_equal(paper$scaling$t_min[["fan_total_efficiency"]], min(seb_sim$fan_total_efficiency))
  logged <- koh_data(seb_field, seb_sim, scales = c(infiltration_per_exterior_area = "log"))
  expect_equal(unname(logged$scaling$t_scale), c("identity", "identity", "log"))
  v <- log(seb_sim$infiltration_per_exterior_area)
  expect_equal(unname(logged$tc[, 3]), (v - min(v)) / diff(range(v)))
})

test_that("a parameter that crosses zero keeps the identity under 'auto'", {
  t <- cbind(a = c(-1, 0.5, 1, 2), b = c(1, 2, 3, 4))
  eta <- 1 / t[, "b"] + t[, "a"]
  expect_equal(bayesbem:::auto_scales(t, matrix(0, 4, 0), eta),
               c(a = "identity", b = "reciprocal"))
})

test_that("bad scales get classed errors", {
  expect_snapshot(koh_data(seb_field, seb_sim, scales = "log"), error = TRUE)
  expect_snapshot(koh_data(seb_field, seb_sim, scales = c(fan = "log")), error = TRUE)
  expect_snapshot(koh_data(seb_field, seb_sim, scales = c(fan_total_efficiency = "sqrt")),
                  error = TRUE)
  sim <- seb_sim
  sim$equipment_power_density <- sim$equipment_power_density - 10
  expect_snapshot(koh_data(seb_field, sim, scales = c(equipment_power_density = "log")),
                  error = TRUE)
  expect_error(koh_data(seb_field, seb_sim, scales = 1), class = "bayesbem_error_argument")
})
