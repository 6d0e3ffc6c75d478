#' ASHRAE Guideline 14 goodness-of-fit metrics
#'
#' `cvrmse()` is the coefficient of variation of the root mean squared error
#' and `nmbe()` the normalised mean bias error, both in percent, as ASHRAE
#' Guideline 14-2014 defines them (section 5.3.2.4; `n - p` degrees of
#' freedom, the mean of the measured values):
#'
#' `CVRMSE = 100 * sqrt(sum((obs - pred)^2) / (n - p)) / mean(obs)`
#'
#' `NMBE = 100 * sum(obs - pred) / ((n - p) * mean(obs))`
#'
#' A positive NMBE means the model predicts too little on average (the
#' Guideline's sign: measured less predicted). `p = 1`, the default, is
#' Chong & Menberg (2018)'s `n - 1`.
#'
#' @param obs Observed values.
#' @param pred Predicted values, the same length as `obs`.
#' @param p Number of the model's parameters, for the degrees of freedom
#'   `n - p`.
#' @return One number, in percent.
#' @family metrics
#' @export
#' @examples
#' obs <- c(100, 110, 120)
#' cvrmse(obs, c(101, 108, 123))
#' nmbe(obs, c(101, 108, 123))
cvrmse <- function(obs, pred, p = 1) {
  check_metric_input(obs, pred, p)
  100 * sqrt(sum((obs - pred)^2) / (length(obs) - p)) / mean(obs)
}

#' @rdname cvrmse
#' @export
nmbe <- function(obs, pred, p = 1) {
  check_metric_input(obs, pred, p)
  100 * sum(obs - pred) / ((length(obs) - p) * mean(obs))
}

check_metric_input <- function(obs, pred, p, call = rlang::caller_env()) {
  if (!is.numeric(obs) || !is.numeric(pred) || length(obs) != length(pred) ||
      length(obs) < 2L || anyNA(obs) || anyNA(pred)) {
    abort_bayesbem(c("{.arg obs} and {.arg pred} must be numeric vectors of the same length (at least 2), without missing values.",
                     x = "They have lengths {length(obs)} and {length(pred)}."),
                   "argument", call = call)
  }
  if (!rlang::is_scalar_integerish(p) || p < 0 || p >= length(obs)) {
    abort_bayesbem("{.arg p} must be a whole number from 0 to {length(obs) - 1}, not {describe_value(p)}.",
                   "argument", call = call)
  }
}

# The calibrated prediction's calibration_metrics() on the training data
# and, unless NULL, on the held-out `newdata` and `obs`.
held_out_metrics <- function(fit, newdata, obs, ndraws) {
  m <- calibration_metrics(fit, newdata = newdata, obs = obs, ndraws = ndraws)
  m <- m[m$prediction == "calibrated", setdiff(names(m), c("prediction", "route"))]
  structure(m, row.names = seq_len(nrow(m)))
}

check_both_or_neither <- function(newdata, obs, call = rlang::caller_env()) {
  if (xor(is.null(newdata), is.null(obs))) {
    abort_bayesbem("Give both {.arg newdata} and {.arg obs} for held-out data, or neither.",
                   "argument", call = call)
  }
}

# Held-out data are both or neither of `newdata` (a data frame with the
# observable inputs) and `obs` (one measured output per row), checked
# before any fit starts; values are checked where they are scaled.
check_held_out <- function(newdata, obs, data, call = rlang::caller_env()) {
  check_both_or_neither(newdata, obs, call)
  if (is.null(newdata)) return(invisible())
  needed <- data$names$x
  if (!is.data.frame(newdata) || !all(needed %in% names(newdata))) {
    abort_bayesbem(c("{.arg newdata} must be a data frame with the observable inputs, {.field {needed}}.",
                     i = "Give the held-out periods' observable inputs (and covariates)."),
                   "columns", call = call)
  }
  if (!is.numeric(obs) || length(obs) != nrow(newdata)) {
    abort_bayesbem("{.arg obs} must be one measured output per row of {.arg newdata} ({nrow(newdata)}), not {describe_value(obs)}.",
                   "argument", call = call)
  }
  invisible()
}

#' Calibration metrics of a KOH fit, with the Guideline 14 verdict
#'
#' Compares predictions with the measured data by [cvrmse()] and [nmbe()]
#' (Guideline 14's definitions, `n - 1`), on the training data and, when
#' given, held-out data, reported apart. Two predictions, labelled:
#' * `"simulator"`: the simulation model at the posterior, `eta(x, tf)`
#'   without the discrepancy: what Guideline 14's compliance is about. By
#'   the emulator, or by the simulator itself when one is given (its
#'   output at posterior draws, as [posterior_simulate()]).
#' * `"calibrated"`: the calibrated prediction `eta + delta`, the
#'   posterior mean; on the training data the discrepancy is fitted to the
#'   same bills, so its figures are in-sample.
#'
#' Guideline 14 calls a model calibrated at CVRMSE <= 15 % and |NMBE| <= 5 %
#' for monthly data, and 30 % and 10 % for hourly data. It sets no limits
#' for daily or weekly data; `by = "day"` or `"week"` applies the hourly ones,
#' the limits the Guideline gives for data finer than monthly.
#'
#' @param fit A `bayesbem_fit`; on several outputs, each output's metrics on
#'   its training data, with a first column `output` (held-out data and
#'   simulators are given output by output, on [output_fit()]).
#' @param newdata Held-out periods: a data frame of observable inputs (the
#'   field inputs' columns; predicted through the emulator), or a
#'   [scenario()] or simulator for them (predicted through the simulator,
#'   see [predict_scenario()]); `NULL` for training data only.
#' @param obs Measured outputs of the held-out periods (`NA` for a period
#'   without a measurement, e.g. the months of a year-long simulator after
#'   the last bill: left out).
#' @param by The data's periods, `"month"`, `"week"`, `"day"` or `"hour"`
#'   (as in [epw_weather()]): which limits apply.
#' @param simulator Optional simulator of the training periods: the
#'   training rows are then predicted through it.
#' @param ndraws Number of posterior draws to use (all by default through
#'   the emulator; 40 through a simulator).
#' @template args-cache-dir
#' @return A data frame (class `bayesbem_metrics`, printed with 2 decimals) with
#'   one row per data set (`set`: `training`, `held-out`) and `prediction`
#'   (`simulator`, `calibrated`): `route` (`emulator` or `simulator`), `n`,
#'   `cvrmse`, `nmbe` (percent) and `calibrated` (within the limits).
#' @family metrics
#' @export
#' @examples
#' calibration_metrics(seb_fit, ndraws = 100)
calibration_metrics <- function(fit, newdata = NULL, obs = NULL,
                                by = c("month", "week", "day", "hour"),
                                simulator = NULL, ndraws = NULL, cache_dir = NULL) {
  match_choice(by)
  check_fit(fit)
  UseMethod("calibration_metrics")
}

#' @export
calibration_metrics.bayesbem_fit <- function(fit, newdata = NULL, obs = NULL,
                                             by = c("month", "week", "day", "hour"),
                                             simulator = NULL, ndraws = NULL, cache_dir = NULL) {
  by <- match_choice(by)
  limits <- if (by == "month") c(15, 5) else c(30, 10)
  check_both_or_neither(newdata, obs)
  sets <- list(training = training_predictions(fit, simulator, ndraws, cache_dir))
  if (!is.null(newdata)) {
    sets[["held-out"]] <- heldout_predictions(fit, newdata, obs, ndraws, cache_dir)
  }
  rows <- lapply(names(sets), function(set) {
    p <- sets[[set]]
    do.call(rbind, lapply(c("simulator", "calibrated"), function(what) {
      cv <- cvrmse(p$obs, p[[what]])
      nb <- nmbe(p$obs, p[[what]])
      data.frame(set = set, prediction = what, route = p$route, n = length(p$obs),
                 cvrmse = cv, nmbe = nb, calibrated = cv <= limits[1] && abs(nb) <= limits[2])
    }))
  })
  structure(do.call(rbind, rows), class = c("bayesbem_metrics", "data.frame"))
}

# calibration_metrics() of each output of a fit on several outputs, on its
# training data, with a first column `output`. Held-out data and simulators
# are an output's own, so they are given output by output.
#' @export
calibration_metrics.bayesbem_fit_outputs <- function(fit, newdata = NULL, obs = NULL,
                                                     by = c("month", "week", "day", "hour"),
                                                     simulator = NULL, ndraws = NULL,
                                                     cache_dir = NULL) {
  each <- output_results(fit, calibration_metrics,
                         list(newdata = newdata, obs = obs, simulator = simulator),
                         by = by, ndraws = ndraws, cache_dir = cache_dir)
  structure(each$table, class = c("bayesbem_metrics", "data.frame"))
}

# Posterior means of the simulator part and of the calibrated prediction at
# the training rows, through the emulator or through `simulator`.
training_predictions <- function(fit, simulator, ndraws, cache_dir,
                                 call = rlang::caller_env()) {
  obs <- fit$data$field[[fit$data$names$y]]
  if (is.null(simulator)) {
    return(emulator_predictions(fit, field_inputs(fit$data), obs, ndraws))
  }
  simulator_predictions(fit, simulator, obs, ndraws, cache_dir,
                        rows = simulator_rows(fit, simulator, call))
}

# Held-out periods without a measurement (NA in `obs`) are left out.
heldout_predictions <- function(fit, newdata, obs, ndraws, cache_dir,
                                call = rlang::caller_env()) {
  if (is.data.frame(newdata)) {
    rows <- measured_periods(obs, nrow(newdata), call = call)
    return(emulator_predictions(fit, newdata[rows, , drop = FALSE], obs[rows], ndraws))
  }
  scenario <- as_scenario(newdata, arg = "newdata", call = call)
  rows <- measured_periods(obs, nrow(scenario$simulator$x), call = call)
  simulator_predictions(fit, scenario, obs[rows], ndraws, cache_dir, rows = rows)
}

# The simulator route: the simulator rerun at `ndraws` posterior draws (40
# by default), its periods `rows` matched to `obs`.
simulator_predictions <- function(fit, simulator, obs, ndraws, cache_dir, rows) {
  p <- predict_scenario(fit, simulator, ndraws = ndraws %||% 40, noise = FALSE,
                        cache_dir = cache_dir)
  list(obs = obs, simulator = colMeans(p$simulated)[rows], calibrated = colMeans(p$y)[rows],
       route = "simulator")
}

emulator_predictions <- function(fit, x, obs, ndraws) {
  draws <- predict_draws(fit, x, ndraws = ndraws)
  list(obs = obs, simulator = colMeans(draws$eta), calibrated = colMeans(draws$y),
       route = "emulator")
}

#' @export
print.bayesbem_metrics <- function(x, ...) {
  rlang::check_dots_empty()
  out <- as.data.frame(unclass(x))
  for (col in intersect(c("cvrmse", "nmbe"), names(out))) {
    out[[col]] <- formatC(out[[col]], format = "f", digits = 2)
  }
  print(out, row.names = FALSE, right = TRUE)
  invisible(x)
}

# The periods with a measurement: `measured` has one value per period of a
# simulator (`n`), NA where there is none (avoided_energy(), held-out
# periods of calibration_metrics()).
measured_periods <- function(measured, n, arg = rlang::caller_arg(measured),
                             call = rlang::caller_env()) {
  if (!is.numeric(measured) || length(measured) != n || any(is.infinite(measured)) ||
      all(is.na(measured))) {
    abort_bayesbem(c("{.arg {arg}} must hold one number per period ({n}).",
                     x = "It is {describe_value(measured)} of length {length(measured)}.",
                     i = "Give NA for a period without a measurement."),
                   "argument", call = call)
  }
  which(!is.na(measured))
}

#' The calibrated simulator beside the M&V regression on held-out hours
#'
#' Judges a calibration against the regression an M&V programme would use
#' otherwise ([towt_baseline()], fitted on the same training hours), on the
#' same held-out periods: each prediction's [cvrmse()] and [nmbe()] and
#' the share of the measured values inside its central `level` interval,
#' hour by hour and for each calendar month's total of the measured
#' hours. The calibrated simulator predicts through the simulator rerun at
#' `ndraws` posterior draws, with its noise ([predict_scenario()]); its
#' intervals are the order statistics of the draws, and a month's total is
#' the sum of its hours draw by draw. The baseline's hourly intervals are
#' its least-squares prediction intervals, its monthly ones Guideline 14's.
#'
#' @param fit A `bayesbem_fit` of hourly data (of one output: give
#'   [output_fit()] of a fit on several).
#' @param baseline A [towt_baseline()] fitted on the training hours.
#' @param newdata A simulator by hour (or a [scenario()] of one) of the
#'   held-out hours; its `temp` and period starts are the baseline's inputs.
#' @param obs The measured use of each of its hours (`NA` where none).
#' @template args-level
#' @param ndraws Number of posterior draws the simulator runs at.
#' @template args-cache-dir
#' @return A data frame (class `bayesbem_metrics`): `prediction`
#'   (`"calibrated"`, `"baseline"`), `by` (`"hour"`, `"month"`), `n`,
#'   `cvrmse`, `nmbe` (percent) and `coverage` (share of `obs` inside the
#'   `level` interval).
#' @family metrics
#' @export
compare_baseline <- function(fit, baseline, newdata, obs, level = 0.9, ndraws = 40,
                             cache_dir = NULL) {
  check_fit(fit)
  check_one_output(fit)
  if (!inherits(baseline, "bayesbem_towt")) {
    abort_bayesbem("{.arg baseline} must be a {.fn towt_baseline}, not {describe_value(baseline)}.",
                   "argument")
  }
  check_probability(level)
  scenario <- as_scenario(newdata, arg = "newdata")
  hours <- scenario$simulator$periods$start
  if (!inherits(hours, "POSIXct") || is.null(scenario$simulator$x$temp)) {
    abort_bayesbem("{.arg newdata} must simulate hours with a {.field temp} input, e.g. {.code bem_simulator(epw, by = \"hour\")}.",
                   "argument")
  }
  rows <- measured_periods(obs, length(hours))
  draws <- predict_scenario(fit, scenario, ndraws = ndraws, noise = TRUE,
                            cache_dir = cache_dir)$y[, rows, drop = FALSE]
  inputs <- data.frame(temp = scenario$simulator$x$temp[rows], time = hours[rows])
  towt <- list(hour = stats::predict(baseline, inputs, level = level),
               month = stats::predict(baseline, inputs, by = "month", level = level))
  month <- format(hours[rows], "%Y-%m", tz = baseline$zone)
  month_draws <- vapply(unique(month), function(m) rowSums(draws[, month == m, drop = FALSE]),
                        numeric(nrow(draws)))
  calibrated <- list(hour = draws, month = matrix(month_draws, nrow = nrow(draws)))
  measured <- list(hour = obs[rows],
                   month = vapply(unique(month), function(m) sum(obs[rows][month == m]), numeric(1),
                                  USE.NAMES = FALSE))
  bounds <- quantile_names(interval_probs(level))
  out <- do.call(rbind, lapply(c("hour", "month"), function(by) {
    intervals <- column_intervals(calibrated[[by]], level)
    rbind(metric_row("calibrated", by, measured[[by]], colMeans(calibrated[[by]]), intervals),
          metric_row("baseline", by, measured[[by]], towt[[by]]$mean,
                     as.matrix(towt[[by]][bounds])))
  }))
  structure(out, class = c("bayesbem_metrics", "data.frame"))
}

# One row of compare_baseline(): Guideline 14's metrics and the share of
# `obs` inside `intervals` (a matrix of lower and upper bounds); a single
# month has no CVRMSE or NMBE (they need two values), only its coverage.
metric_row <- function(prediction, by, obs, mean, intervals) {
  two <- length(obs) >= 2L
  data.frame(prediction = prediction, by = by, n = length(obs),
             cvrmse = if (two) cvrmse(obs, mean) else NA_real_,
             nmbe = if (two) nmbe(obs, mean) else NA_real_,
             coverage = mean(obs >= intervals[, 1] & obs <= intervals[, 2]))
}
