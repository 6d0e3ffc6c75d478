# A fast simulator of seb_fit's parameters, linear in them: its outputs at
# any draw can be written down by hand.
linear_seb_simulator <- function(weather = seb_field[c("temp", "rh", "solar")]) {
  parameters <- bem_parameters()
  simulator(function(params, x) {
    1000 + 40 * params$equipment_power_density - 300 * params$fan_total_efficiency +
      2e5 * params$infiltration_per_exterior_area + 5 * abs(x$temp - 15) +
      10 * params$lighting_power_density
  }, x = weather, parameters = parameters, name = "linear")
}

# The posterior draws a scenario prediction used, in physical units.
used_draws <- function(fit, index) {
  as.data.frame(posterior::as_draws_df(fit))[index, fit$data$names$t]
}

# A fit whose emulator is exact: runs of a simulator linear in its inputs
# and parameters, which the emulator's linear mean reproduces, so that the
# emulator route and the simulator route must agree. Made once per test run.
linear_case <- local({
  case <- NULL
  function() {
    if (is.null(case)) {
      sim <- simulator(function(params, x) {
        1000 + 40 * params$equipment_power_density + 2e5 * params$infiltration_per_exterior_area +
          8 * x$temp - 2 * x$rh
      }, x = seb_field[c("temp", "rh", "solar")], parameters = bem_parameters(), name = "linear")
      truth <- list(equipment_power_density = 15, infiltration_per_exterior_area = 0.0008)
      field <- simulate_field(sim, truth, noise_sd = 10, seed = 2)
      ranges <- sim$parameters[sim$parameters$parameter %in% names(truth), ]
      runs <- simulate_design(sim, design_lhs(ranges, n = 15, seed = 1))
      fit <- suppressWarnings(
        calibrate(koh_data(field, runs, scales = "identity"), chains = 2, iter = 1000, seed = test_seed(1),
                  cores = 2, refresh = 0),
        classes = "bayesbem_warning_convergence")
      case <<- list(sim = sim, field = field, fit = fit)
    }
    case
  }
})
