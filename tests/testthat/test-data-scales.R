# The sum of squared errors with which lm(formula) predicts each run from a
# fit to the other runs, by refitting without it.
left_out_by_refits <- function(formula, data, run) {
  sum(vapply(unique(run), function(r) {
    fit <- stats::lm(formula, data = data[run != r, ])
    sum((data$eta[run == r] - stats::predict(fit, data[run == r, ]))^2)
  }, numeric(1)))
}

test_that("scales = 'auto' puts fan efficiency on the reciprocal scale, the others as they are", {
  d <- koh_data(seb_field, seb_sim)
  expect_equal(d$scaling$t_scale,
               c(fan_total_efficiency = "reciprocal", equipment_power_density = "identity",
                 infiltration_per_exterior_area = "identity"))
  # independently: the error with which the runs' linear fit on the inputs and
  # parameters predicts each run left out, refitted without it, fan
  # efficiency as it is and as 1 / efficiency
  run <- bayesbem:::row_groups(as.matrix(seb_sim[5:7]))
  ratio <- left_out_by_refits(eta ~ temp + rh + solar + I(1 / fan_total_efficiency) +
                                equipment_power_density + infiltration_per_exterior_area,
                              seb_sim, run) /
    left_out_by_refits(eta ~ temp + rh + solar + fan_total_efficiency + equipment_power_density +
                         infiltration_per_exterior_area, seb_sim, run)
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
  t <- cbind(a = c(-1, 0.5, 1, 2, -0.5, 1.5, 0.2, 3), b = 1:8)
  eta <- 1 / t[, "b"] + t[, "a"]
  expect_equal(bayesbem:::auto_scales(t, matrix(0, 8, 0), eta),
               c(a = "identity", b = "reciprocal"))
})

test_that("the left-out error equals refits without each run", {
  X <- cbind(1, as.matrix(seb_sim[c("temp", "rh", "solar", "fan_total_efficiency")]))
  run <- bayesbem:::row_groups(as.matrix(seb_sim[5:7]))
  expect_equal(bayesbem:::left_out_ss(X, seb_sim$eta, run),
               left_out_by_refits(eta ~ temp + rh + solar + fan_total_efficiency, seb_sim, run),
               tolerance = 1e-10)
  # a run that alone determines a coefficient cannot be predicted by the others
  expect_equal(bayesbem:::left_out_ss(cbind(1, c(1, 0, 0)), c(1, 2, 3), 1:3), Inf)
})

test_that("'auto' does not pick a scale that only fits the run nearest 0", {
  # a linear output in a parameter whose range reaches down to 0: on the
  # reciprocal scale the run at 1e-6 lies far from the others, and a fit to
  # every run matches it, but none predicts it when it is left out
  t <- cbind(a = c(1e-6, seq(0.1, 1, length.out = 9)))
  eta <- 0.05 * t[, "a"] + c(1, 0, 0.05, -0.04, 0.02, 0, -0.03, 0.01, 0.02, -0.01)
  rss <- function(v) sum(stats::lm.fit(cbind(1, v), eta)$residuals^2)
  expect_lt(rss(-1 / t[, "a"]), 0.8 * rss(t[, "a"]))
  expect_equal(bayesbem:::auto_scales(t, matrix(0, 10, 0), eta), c(a = "identity"))
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
