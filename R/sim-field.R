#' Synthetic field data with a known truth
#'
#' Runs a simulator at known parameter values and adds an optional hidden
#' effect and measurement noise, so that the whole pipeline (calibration,
#' [discrepancy()], [explain_discrepancy()], [extend()], [compare_fits()])
#' can be checked against the truth. With [bem_simulator()] on several
#' years of weather (`rbind()` of [epw_monthly()] tables) there are enough
#' field months for the discrepancy tools.
#'
#' @param simulator A `bayesbem_simulator`.
#' @param truth A named list (or one-row data frame) of true parameter
#'   values, physical units; parameters not named are at their initial
#'   values.
#' @param covariates Optional data frame with one row per simulator period
#'   of variables the simulator does not use (occupancy, a calendar flag,
#'   ...), returned as extra columns and available to `effect`.
#' @param effect Optional hidden effect: a function of a data frame with the
#'   observable inputs and the covariates, returning one number per period
#'   (output units), added to the simulator output.
#' @param noise_sd Standard deviation of the Gaussian measurement noise.
#' @param seed Random seed of the noise.
#' @return A data frame `[y, x, covariates]` in the layout [calibrate()]
#'   takes, with attributes `truth` (all parameter values), `simulated` (the
#'   noise-free simulator output) and `effect` (the hidden effect per period).
#' @family simulation
#' @export
#' @examples
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' field <- simulate_field(sim, list(equipment_power_density = 15),
#'                         effect = function(d) 3 * d$rh, noise_sd = 20, seed = 1)
#' head(field)
simulate_field <- function(simulator, truth, covariates = NULL, effect = NULL, noise_sd = 0,
                           seed = NULL) {
  if (!inherits(simulator, "bayesbem_simulator")) {
    abort_bayesbem(c("{.arg simulator} must be a simulator.",
                     i = "Make one with {.fn simulator} or {.fn bem_simulator}."),
                   "argument")
  }
  check_number(noise_sd, "argument")
  params <- design_settings(simulator, as.data.frame(as.list(truth)))[[1]]
  x <- simulator$x
  inputs <- x
  if (!is.null(covariates)) {
    covariates <- as_numeric_table(covariates, "covariates")
    if (nrow(covariates) != nrow(x)) {
      abort_bayesbem(c("{.arg covariates} must have one row per simulator period ({nrow(x)}).",
                       x = "It has {nrow(covariates)}."),
                     "covariates")
    }
    inputs <- cbind(x, covariates)
  }
  simulated <- simulator$fun(params, x)
  hidden <- if (is.null(effect)) rep(0, nrow(x)) else effect(inputs)
  if (!is.numeric(hidden) || length(hidden) != nrow(x) || any(!is.finite(hidden))) {
    abort_bayesbem(c("{.arg effect} must return one finite number per period ({nrow(x)}).",
                     x = "It returned {.obj_type_friendly {hidden}} of length {length(hidden)}."),
                   "argument")
  }
  noise <- with_seed(seed, stats::rnorm(nrow(x), sd = noise_sd))
  structure(data.frame(y = simulated + hidden + noise, inputs, row.names = NULL),
            truth = params, simulated = simulated, effect = hidden)
}
