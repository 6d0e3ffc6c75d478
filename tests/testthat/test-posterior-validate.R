test_that("the emulator of a fit on the right simulator passes the closed loop", {
  case <- synthetic_case("none")
  sim <- synthetic_simulator()
  check <- validate_emulator(case$base, sim, ndraws = 8)
  expect_s3_class(check, "bayesbem_emulator_check")
  expect_equal(nrow(check$table), 8 * 36)
  # the simulator's outputs, recomputed independently at the draws' parameters
  tf <- bayesbem:::parameter_draws(case$base)[unique(check$table$draw), ]
  design <- as.data.frame(unclass(tf)[, c("equipment_power_density", "infiltration_per_exterior_area")])
  direct <- simulate_design(sim, design)
  rows <- match(bayesbem:::row_keys(as.matrix(case$base$data$field[c("temp", "rh", "solar")])),
                bayesbem:::row_keys(as.matrix(sim$x)))
  expect_equal(check$table$simulated,
               as.vector(t(matrix(direct$eta, nrow = 8, byrow = TRUE)[, rows])))
  expect_gte(check$coverage, 0.8)
  expect_true(check$trusted)
  expect_match(check$verdict, "can be trusted")
  expect_equal(nrow(check$periods), 36)
  expect_equal(check$coverage, mean(check$table$simulated >= check$table$lower &
                                      check$table$simulated <= check$table$upper))
  # the right simulator's outputs barely move the calibration
  expect_equal(check$shift$parameter, names(synthetic_truth))
  expect_equal(dim(attr(check$shift, "draws")), c(8, 2))
  expect_true(all(abs(check$shift$shift) < 0.5))
  # the real simulator's output distribution at the posterior
  # (8 draws are too few for its 90 % intervals, which it says)
  expect_warning(ps <- posterior_simulate(case$base, sim, ndraws = 8),
                 class = "bayesbem_warning_draws")
  expect_equal(ps$mean, colMeans(matrix(check$table$simulated, nrow = 8, byrow = TRUE)))
})

test_that("a simulator other than the fit's is exposed, with the reason", {
  case <- synthetic_case("none")
  other <- synthetic_simulator()
  shifted <- simulator(function(params, x) 1.3 * other$fun(params, x), other$x, other$parameters)
  check <- validate_emulator(case$base, shifted, ndraws = 4)
  expect_false(check$trusted)
  expect_lt(check$coverage, 0.2)
  expect_match(check$verdict, "cannot be trusted")
  expect_s3_class(plot(check), "ggplot")
  d <- plot_emulator_check_data(check)
  expect_true(all(abs(d$position - d$period) <= 0.3 + 1e-12))
})

test_that("the calibration shift is the step to where the simulator's outputs fit best", {
  # outputs that are the emulator's at tf + d: the likelihood given the runs
  # peaks at tf + d, so the shift is d (to second order in d and in the
  # sensitivity's finite differences), on the grid and the dense algebra
  data <- seb_fit$data
  par <- bayesbem:::draw_parameters(seb_fit, 5)[[3]]
  d <- c(0.004, -0.003, 0.002)
  for (structure in c("grid", "dense")) {
    g <- bayesbem:::gp_geometry(data, NULL, structure)
    s <- bayesbem:::runs_mean(g, par, par$tf + d)
    expect_equal(bayesbem:::emulator_shift(g, par, s)$shift, d, tolerance = 0.05)
  }
})

test_that("the shift's stated sd is the spread of the shifts the emulator's stated error causes", {
  # outputs drawn from the emulator's own predictive given the runs,
  # N(m(tf), S_e): the shifts' sample sds match the stated sd
  withr::local_seed(8)
  data <- seb_fit$data
  par <- bayesbem:::draw_parameters(seb_fit, 5)[[2]]
  g <- bayesbem:::gp_geometry(data, NULL, "grid")
  fm <- bayesbem:::runs_field(g, par)
  s_e <- fm$cov - bayesbem:::delta_cov(g$ff, par) - diag(1 / par$lambda_e, data$n)
  e <- eigen(s_e, symmetric = TRUE)
  root <- e$vectors %*% diag(sqrt(pmax(e$values, 0)))
  draws <- fm$mean + root %*% matrix(stats::rnorm(data$n * 400), data$n)
  shifts <- t(apply(draws, 2, function(s) bayesbem:::emulator_shift(g, par, s)$shift))
  stated <- bayesbem:::emulator_shift(g, par, fm$mean)
  expect_equal(stated$shift, rep(0, data$q), tolerance = 1e-8)
  expect_equal(apply(shifts, 2, stats::sd), stated$sd, tolerance = 0.1)
})

test_that("an emulator whose error moves a parameter is not trusted, and the verdict names it", {
  case <- synthetic_case("none")
  sim <- synthetic_simulator()
  # the simulator's outputs at equipment density 2 posterior sds higher:
  # the emulator's error is then the parameter's effect
  sd_equipment <- stats::sd(bayesbem:::parameter_draws(case$base)[, "equipment_power_density"])
  offset <- simulator(function(params, x) {
    params$equipment_power_density <- params$equipment_power_density + 2 * sd_equipment
    sim$fun(params, x)
  }, sim$x, sim$parameters)
  check <- validate_emulator(case$base, offset, ndraws = 8)
  expect_false(check$trusted)
  expect_equal(check$shift$shift[1], 2, tolerance = 0.15)
  expect_gt(abs(check$shift$z[1]), stats::qnorm(1 - 0.05 / 2))
  expect_lt(abs(check$shift$shift[2]), 0.5)
  expect_match(check$verdict, "moves equipment_power_density by [12][.][0-9]+ posterior sd")
  expect_output(print(check), "Shift of the calibration")
})

test_that("validate_emulator() checks its inputs", {
  sim <- bem_simulator(shipped_epw(2013))
  expect_error(validate_emulator(seb_fit, sim, ndraws = 0), class = "bayesbem_error_argument")
  expect_error(validate_emulator(seb_fit, sim, level = 2), class = "bayesbem_error_argument")
  expect_error(validate_emulator(seb_fit, list()), class = "bayesbem_error_argument")
  expect_error(validate_emulator(seb_fit, sim, n_draws = 5), class = "rlib_error_dots_nonempty")
  # the shipped fit's solar inputs are not the weather file's direct normal radiation
  expect_snapshot(check <- validate_emulator(seb_fit, sim, ndraws = 2))
  expect_equal(nrow(check$table), 2 * 12)
  daily <- bem_simulator(epw_daily(shipped_epw(2013)))
  expect_snapshot(validate_emulator(seb_fit, daily, ndraws = 2), error = TRUE)
  lin <- simulator(function(params, x) params$a * x$temp, x = sim$x,
                   parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  expect_snapshot(validate_emulator(seb_fit, lin, ndraws = 2), error = TRUE)
})
