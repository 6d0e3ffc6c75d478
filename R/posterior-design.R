#' Runs where the posterior lies: a design to refine the emulator
#'
#' The next step when [validate_emulator()] says the emulator cannot be
#' trusted for a posterior. `design_posterior()` lays a maximin Latin
#' hypercube (package lhs) over the central `level` interval of each
#' calibration parameter's posterior, so the simulator runs where the
#' calibration needs the emulator to be right. The hypercube is laid on the
#' scale the emulator works on (see `scales` in [koh_data()]: a parameter
#' on the log scale is spread evenly in its logarithm) and returned in
#' physical units. Run it with [simulate_design()], bind the result to the
#' earlier runs and calibrate again.
#'
#' Why: a Gaussian-process emulator is only as good as the runs near the
#' posterior. With many field rows (a year of daily data) the posterior is
#' narrow, and the emulator's error between the runs can hold it off the
#' truth, e.g. at one end of a ridge of parameters that trade off. Runs over
#' its region move it; repeat while the posterior still moves
#' ([refine_emulator()] does).
#'
#' @param fit A `bayesbem_fit`, of one output or several (whose outputs
#'   share the calibration parameters and their runs).
#' @param n Number of runs.
#' @param level Probability mass of the central posterior interval each
#'   parameter's runs span.
#' @param seed Random seed of the hypercube.
#' @param ... Unused.
#' @return A data frame with `n` rows and one column per calibration
#'   parameter, in physical units: the `design` of [simulate_design()].
#' @family design
#' @export
#' @examples
#' design_posterior(seb_fit, n = 5, seed = 1)
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' runs <- simulate_design(sim, design_posterior(seb_fit, n = 5, seed = 1))
#' head(runs)
#' }
design_posterior <- function(fit, n, level = 0.9, seed = NULL, ...) {
  rlang::check_dots_empty()
  check_fit(fit)
  check_run_count(n)
  check_probability(level)
  # the calibration parameters and their scales are every output's
  fit <- output_fit_list(fit)[[1]]
  # tf is on the emulator's [0, 1] scale, so quantiles and strata are too
  tf <- stan_draws(fit, "tf")
  ends <- apply(tf, 2, stats::quantile, c(1 - level, 1 + level) / 2)
  design <- unscale_t(maximin_box(n, ends[1, ], ends[2, ], seed), fit$data$scaling)
  stats::setNames(as.data.frame(design), fit$data$names$t)
}
