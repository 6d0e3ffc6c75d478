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

# A synthetic calibration problem of the reliability benchmark
# (bench/bench-reliability.R) and its tests: the embedded model on n periods
# (months of 2012, 2013 and a perturbed copy of 2013 for n <= 36; n days of
# 2013, evenly spaced, above), the paper's three calibration parameters with
# the truth drawn within the middle 80 % of their ranges, noise 2 % of the
# mean output, and a maximin LHS design of mt runs at every period; `k`
# seeds the draw. Returns the field table, the runs, the truth and the
# simulator (for runs added later, e.g. by design_posterior()).
synthetic_problem <- function(n, mt, k) {
  sim <- bem_simulator(synthetic_weather(n))
  names <- c("fan_total_efficiency", "equipment_power_density", "infiltration_per_exterior_area")
  params <- sim$parameters[sim$parameters$parameter %in% names, ]
  truth <- with_seed(1000 + k, {
    u <- stats::runif(nrow(params), 0.1, 0.9)
    stats::setNames(as.list(params$min + u * (params$max - params$min)), params$parameter)
  })
  clean <- simulate_field(sim, truth)
  list(field = simulate_field(sim, truth, noise_sd = 0.02 * mean(clean$y), seed = 2000 + k),
       runs = simulate_design(sim, design_lhs(params, n = mt, seed = 3000 + k)),
       truth = truth, simulator = sim)
}

synthetic_weather <- function(n) {
  epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
  if (n > 36) {
    daily <- epw_daily(epw(2013))
    return(daily[unique(round(seq(1, nrow(daily), length.out = n))), ])
  }
  year <- epw_monthly(epw(2013))
  perturbed <- with_seed(7, within(year, {
    temp <- temp + stats::rnorm(12, sd = 1.5)
    rh <- rh + stats::rnorm(12, sd = 4)
    dni <- dni * stats::runif(12, 0.9, 1.1)
  }))
  utils::head(rbind(epw_monthly(epw(2012)), year, perturbed), n)
}
