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
#'   (output units), added to the simulator output. For a simulator of
#'   several outputs, a named list of such functions, one per output it
#'   affects.
#' @param noise_sd Standard deviation of the Gaussian measurement noise; for
#'   a simulator of several outputs, one number for all or a named vector
#'   with one per output (in each output's units; an output not named gets
#'   none). Periods of different lengths (an input `days`) get the noise
#'   [koh_data()] assumes: `noise_sd` is that of a period of the mean
#'   length, and the variance of each is proportional to its days.
#' @param seed Random seed of the noise.
#' @return A data frame `[y, x, covariates]` in the layout [calibrate()]
#'   takes, with attributes `truth` (all parameter values), `simulated` (the
#'   noise-free simulator output) and `effect` (the hidden effect per period).
#'   For a simulator of several outputs, the long table `[output, y, x,
#'   covariates]` with each output's periods in turn, its attributes
#'   `simulated` and `effect` stacked in the same order.
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
  if (is.data.frame(simulated)) {
    return(field_outputs(simulated, inputs, params, effect, noise_sd, seed))
  }
  check_number(noise_sd, "argument")
  hidden <- hidden_effect(effect, inputs)
  noise <- with_seed(seed, stats::rnorm(nrow(x), sd = noise_sd * sqrt(period_weights(x))))
  structure(data.frame(y = simulated + hidden + noise, inputs, row.names = NULL),
            truth = params, simulated = simulated, effect = hidden)
}

# `effect(inputs)` (zero without one), checked: one finite number per period.
hidden_effect <- function(effect, inputs, arg = "effect", call = rlang::caller_env()) {
  if (is.null(effect)) {
    return(rep(0, nrow(inputs)))
  }
  hidden <- effect(inputs)
  if (!is.numeric(hidden) || length(hidden) != nrow(inputs) || any(!is.finite(hidden))) {
    abort_bayesbem(c("{.arg {arg}} must return one finite number per period ({nrow(inputs)}).",
                     x = "It returned {.obj_type_friendly {hidden}} of length {length(hidden)}."),
                   "argument", call = call)
  }
  hidden
}

# simulate_field() of a simulator of several outputs: the long table, each
# output with its own effect and noise (drawn output after output).
field_outputs <- function(simulated, inputs, params, effect, noise_sd, seed,
                          call = rlang::caller_env()) {
  outputs <- names(simulated)
  check_output_names(effect, outputs, "effect", is.function, sprintf("list(%s = function(d) ...)", outputs[1]), call)
  check_output_names(noise_sd, outputs, "noise_sd", function(v) is.numeric(v) && v >= 0,
                     sprintf("c(%s = 10)", outputs[1]), call)
  if (length(noise_sd) == 1L && is.null(names(noise_sd))) {
    noise_sd <- stats::setNames(rep(noise_sd, length(outputs)), outputs)
  }
  noise <- with_seed(seed, lapply(outputs, function(k) {
    sd <- if (k %in% names(noise_sd)) noise_sd[[k]] else 0
    stats::rnorm(nrow(inputs), sd = sd * sqrt(period_weights(inputs)))
  }))
  rows <- lapply(seq_along(outputs), function(j) {
    k <- outputs[j]
    hidden <- hidden_effect(effect[[k]], inputs, sprintf("effect$%s", k), call)
    data.frame(output = k, y = simulated[[k]] + hidden + noise[[j]], inputs,
               simulated = simulated[[k]], effect = hidden, row.names = NULL)
  })
  out <- do.call(rbind, rows)
  structure(out[setdiff(names(out), c("simulated", "effect"))], truth = params,
            simulated = out$simulated, effect = out$effect)
}

# A per-output argument names only outputs the simulator has, each value
# valid; one unnamed value is allowed where `valid` takes it alone.
check_output_names <- function(value, outputs, arg, valid, example, call) {
  if (is.null(value)) {
    return(invisible())
  }
  if (is.null(names(value)) && length(value) == 1L && !is.function(value) && valid(value)) {
    return(invisible())
  }
  unknown <- setdiff(names(value), outputs)
  if (is.null(names(value)) || length(unknown) > 0L || !all(vapply(value, valid, logical(1)))) {
    abort_bayesbem(c("With several outputs, {.arg {arg}} must be named by output.",
                     i = "The simulator's outputs are {.val {outputs}}; e.g. {.code {arg} = {example}}."),
                   "argument", call = call)
  }
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
