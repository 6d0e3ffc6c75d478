#' Scenarios: the calibrated model under other weather or a retrofit
#'
#' A scenario is a question put to the calibrated model: a simulator for
#' the period asked about (its weather: another year, a typical year, a
#' reporting period) and changes to the model's parameters. `set` gives
#' parameters new values; `scale` multiplies them (`0.7` for 30 % less
#' equipment power). A calibrated parameter that is scaled is scaled draw
#' by draw, so its posterior uncertainty carries over; one that is set
#' loses it. Parameters the fit did not calibrate are at the simulator's
#' initial values unless the scenario sets or scales them. A change that
#' no parameter expresses (an EnergyPlus measure: new windows, another HVAC
#' system) is a simulator of its own: edit the model ([eplus_set()],
#' [eplus_add()]) and make [eplus_simulator()] of it with the same weather.
#'
#' @param simulator A `bayesbem_simulator` for the scenario's periods
#'   ([bem_simulator()], [eplus_simulator()] or [simulator()]) with the
#'   fit's calibration parameters among its parameters.
#' @param set,scale Named numeric vectors (or lists) of new values and of
#'   multipliers; a parameter may be in one of them, not both.
#' @param name A short label, for printing.
#' @return A `bayesbem_scenario`.
#' @family prediction
#' @export
#' @examples
#' sim <- bem_simulator(system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem"))
#' scenario(sim)
#' scenario(sim, scale = c(equipment_power_density = 0.7), name = "efficient equipment")
scenario <- function(simulator, set = NULL, scale = NULL, name = NULL) {
  check_simulator(simulator)
  set <- scenario_changes(set, simulator)
  scale <- scenario_changes(scale, simulator)
  both <- intersect(names(set), names(scale))
  if (length(both) > 0L) {
    abort_bayesbem(c("{.field {both}} {?is/are} both set and scaled.",
                     i = "Give each parameter in {.arg set} or in {.arg scale}, not both."),
                   "scenario")
  }
  if (any(scale <= 0)) {
    abort_bayesbem(c("{.arg scale} must hold positive multipliers.",
                     x = "{.field {names(scale)[scale <= 0]}} {?is/are} not positive."),
                   "scenario")
  }
  check_scenario_range(simulator, as.data.frame(as.list(set)), "set")
  name <- name %||% scenario_label(set, scale)
  structure(list(simulator = simulator, set = set, scale = scale, name = name),
            class = "bayesbem_scenario")
}

#' @export
print.bayesbem_scenario <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_scenario}: {x$name}",
            "* simulator: {x$simulator$name}, {nrow(x$simulator$x)} period{?s}")
  invisible(x)
}

check_simulator <- function(simulator, arg = rlang::caller_arg(simulator),
                            call = rlang::caller_env()) {
  if (!inherits(simulator, "bayesbem_simulator")) {
    abort_bayesbem(c("{.arg {arg}} must be a simulator, not {describe_value(simulator)}.",
                     i = "Make one with {.fn simulator}, {.fn bem_simulator} or {.fn eplus_simulator}."),
                   "argument", call = call)
  }
}

# A scenario's `set` or `scale` as a named numeric vector of the simulator's
# parameters.
scenario_changes <- function(changes, simulator, arg = rlang::caller_arg(changes),
                             call = rlang::caller_env()) {
  if (is.null(changes) || length(changes) == 0L) {
    return(stats::setNames(numeric(), character()))
  }
  values <- if (is.list(changes)) unlist(changes) else changes
  if (!is.numeric(values) || length(values) != length(changes) || is.null(names(changes)) ||
      any(!nzchar(names(changes))) || any(!is.finite(values))) {
    abort_bayesbem(c("{.arg {arg}} must be a named vector of finite numbers, one per parameter.",
                     i = "For example {.code c(equipment_power_density = 0.7)}."),
                   "scenario", call = call)
  }
  unknown <- setdiff(names(values), simulator$parameters$parameter)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg {arg}} names {.field {unknown}}, not {?a parameter/parameters} of the simulator.",
                     i = "Its parameters are {.field {simulator$parameters$parameter}}."),
                   "scenario", call = call)
  }
  values
}

scenario_label <- function(set, scale) {
  parts <- c(sprintf("%s = %s", names(set), format(set)),
             sprintf("%s x %s", names(scale), format(scale)))
  if (length(parts) == 0L) "as calibrated" else paste(parts, collapse = ", ")
}

# A design's values must lie within the simulator's parameter ranges; the
# error names the parameter, how many draws leave its range and the range.
check_scenario_range <- function(simulator, design, what, call = rlang::caller_env()) {
  table <- simulator$parameters
  for (name in names(design)) {
    row <- table[table$parameter == name, ]
    out <- design[[name]] < row$min | design[[name]] > row$max
    if (any(out)) {
      where <- if (what == "set") "" else " in {sum(out)} of {length(out)} draw{?s}"
      abort_bayesbem(c(paste0("The scenario's {what} puts {.field {name}} at {signif(min(design[[name]][out]), 3)}{if (sum(out) > 1) paste0(' to ', signif(max(design[[name]][out]), 3))}", where, ", outside its range [{row$min}, {row$max}]."),
                       i = "Change the scenario, or widen the range in the simulator's parameter table if the simulator is valid there."),
                     "scenario", call = call)
    }
  }
}

#' Predict through the simulator: another weather, a retrofit
#'
#' `predict_scenario()` predicts the building's use under a [scenario()]
#' by running the simulator at `ndraws` posterior draws of the calibration
#' parameters (through [simulate_design()], so the `future` plan and
#' `cache_dir` apply) instead of extrapolating the emulator: the emulator
#' was learnt at the weather of the runs, and outside it a Gaussian process
#' reverts to its mean (a linear mean extrapolates energy linearly in
#' temperature). Each draw's prediction is the simulator's output `s` plus
#' the discrepancy at the scenario's inputs, drawn from its conditional
#' given the data and `eta = s` there under that draw's hyperparameters
#' (so at the field inputs the simulator route and [predict.bayesbem_fit()]
#' agree where the emulator is right), plus, with `noise = TRUE`, the
#' observation noise (a predicted bill rather than the expected use).
#' Outside the weather the model was calibrated on the discrepancy reverts
#' to its mean, with a warning of class `bayesbem_warning_extrapolation`.
#'
#' Without a simulator for the new period, [predict.bayesbem_fit()] predicts at
#' new inputs through the emulator, with its extrapolation warning.
#'
#' @param fit A `bayesbem_fit`.
#' @param scenario A [scenario()], or a simulator (the scenario with no
#'   change).
#' @template args-ndraws-runs
#' @param discrepancy What the scenario does to the discrepancy, the part of
#'   the measured use the simulator misses: `"same"` (default) adds the
#'   discrepancy at the scenario's inputs; `"proportional"` scales it by the
#'   scenario's simulated use over the calibrated model's under the same
#'   weather (a simulator that misses a share of the loads the scenario
#'   changes; one more run per draw when the scenario changes parameters);
#'   `"none"` leaves it out (the simulator alone). The same choice as
#'   [savings()]'s and [avoided_energy()]'s.
#' @param noise Add observation noise.
#' @param covariates For a fit with discrepancy terms ([extend()]): their
#'   values at the scenario's periods, a data frame with one row per period.
#' @template args-cache-dir
#' @template args-total
#' @param ... Unused.
#' @section Several outputs: On a fit on several outputs the scenario's
#'   simulator gives them all (e.g. `bem_simulator(output = c("electricity",
#'   "gas"))`); each run at a draw serves every output, each output is
#'   predicted as above from the same draws, and `total` weights them into
#'   a total (site energy, cost). `covariates` is then a list of tables by
#'   output. The result, a `bayesbem_scenario_predictions`, holds each
#'   output's prediction in `outputs` and the total's draws in `total`;
#'   `summary()` stacks their summaries with a first column `output`.
#' @return A `bayesbem_scenario_prediction`: a list with `y` (draws by periods:
#'   the prediction), `simulated` (the simulator's outputs) and `delta`
#'   (the discrepancy; zero without it), `inputs` (the scenario's
#'   observable inputs), `draw` (the posterior draws' indices) and
#'   `scenario`. `summary()` gives per period and in total the mean, sd and
#'   quantiles.
#' @family prediction
#' @export
#' @examples
#' \donttest{
#' # seb_fit's runs are EnergyPlus's; the embedded model stands in here
#' sim_2012 <- bem_simulator(system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem"))
#' p <- predict_scenario(seb_fit, sim_2012, ndraws = 10)
#' p
#' summary(p)
#' }
predict_scenario <- function(fit, scenario, ndraws = 40,
                             discrepancy = c("same", "proportional", "none"), noise = TRUE,
                             covariates = NULL, cache_dir = NULL, total = NULL, ...) {
  rlang::check_dots_empty()
  discrepancy <- match_choice(discrepancy)
  if (inherits(fit, "bayesbem_outputs_fit")) {
    return(predict_scenario_outputs(fit, scenario, ndraws, discrepancy, noise, covariates,
                                    cache_dir, total))
  }
  check_fit(fit)
  if (!is.null(total)) {
    abort_bayesbem("{.arg total} adds the outputs of a fit on several outputs; this fit has one.",
                   "argument")
  }
  scenario <- as_scenario(scenario)
  check_bool(noise)
  changed <- length(scenario$set) + length(scenario$scale) > 0L
  scenarios <- list(scenario)
  if (discrepancy == "proportional" && changed) {
    scenarios$calibrated <- as_scenario(scenario$simulator)
  }
  runs <- scenario_runs(fit, scenarios, ndraws, cache_dir)
  simulated <- runs$simulated[[1]]
  inputs <- scenario_inputs(fit, scenario, covariates)
  delta <- if (discrepancy == "none") {
    0 * simulated
  } else {
    calibrated <- runs$simulated[[length(scenarios)]]
    delta <- scenario_delta(fit, inputs, calibrated, runs$draws)
    if (discrepancy == "proportional") delta * simulated / calibrated else delta
  }
  y <- simulated + delta
  if (noise) y <- y + noise_draws(fit, runs$draws, ncol(y))
  structure(list(y = y, simulated = simulated, delta = delta, inputs = scenario$simulator$x,
                 draw = runs$index, scenario = scenario, discrepancy = discrepancy,
                 noise = noise),
            class = "bayesbem_scenario_prediction")
}

#' @export
summary.bayesbem_scenario_prediction <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  draws_with_total(object$y, object$inputs, level)
}

#' @export
print.bayesbem_scenario_prediction <- function(x, ...) {
  rlang::check_dots_empty()
  parts <- c("the simulator",
             if (x$discrepancy != "none") sprintf("the discrepancy (%s)", x$discrepancy),
             if (x$noise) "noise")
  cat_lines("{.cls bayesbem_scenario_prediction}: {x$scenario$name}",
            "* {x$scenario$simulator$name}, {ncol(x$y)} period{?s}",
            "* {nrow(x$y)} posterior draw{?s}: {and_list(parts)}", "")
  print_rounded(summary(x), 4)
  invisible(x)
}

# predict_scenario() of a fit on several outputs (see its section).
predict_scenario_outputs <- function(fit, scenario, ndraws, discrepancy, noise, covariates,
                                     cache_dir, total, call = rlang::caller_env()) {
  scenario <- as_scenario(scenario, "scenario", call = call)
  shared <- shared_runs(scenario$simulator)
  outputs <- names(fit$outputs)
  preds <- lapply(stats::setNames(outputs, outputs), function(k) {
    one <- scenario
    one$simulator <- output_simulator(shared, k)
    predict_scenario(fit$outputs[[k]], one, ndraws = ndraws, discrepancy = discrepancy,
                     noise = noise, covariates = covariates[[k]], cache_dir = cache_dir)
  })
  draw <- lapply(preds, `[[`, "draw")
  y_total <- if (!is.null(total)) {
    check_total_weights(total, lapply(preds, `[[`, "inputs"), call = call)
    weighted_total(total, lapply(preds, `[[`, "y"), draw)
  }
  structure(list(outputs = preds, total = y_total, weights = total, draw = Reduce(intersect, draw),
                 scenario = scenario),
            class = "bayesbem_scenario_predictions")
}

# A simulator whose runs are made once for every output asked of it in
# this session (output_simulator() of it, one per output): its function
# keeps each run's outputs by parameter values. Its cache key stays the
# simulator's own.
shared_runs <- function(simulator) {
  made <- new.env(parent = emptyenv())
  fun <- simulator$fun
  key <- simulator_key(simulator)
  simulator$fun <- function(params, x) {
    id <- rlang::hash(list(params, x))
    if (is.null(made[[id]])) made[[id]] <- fun(params, x)
    made[[id]]
  }
  simulator$key <- key
  simulator
}

#' @export
summary.bayesbem_scenario_predictions <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  rows <- lapply(names(object$outputs), function(k) {
    cbind(output = k, summary(object$outputs[[k]], level = level))
  })
  if (!is.null(object$total)) {
    inputs <- object$outputs[[names(object$weights)[1]]]$inputs
    rows <- c(rows, list(cbind(output = "total", draws_with_total(object$total, inputs, level))))
  }
  do.call(rbind, rows)
}

#' @export
print.bayesbem_scenario_predictions <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_scenario_predictions}: {x$scenario$name}",
            "* {x$scenario$simulator$name}",
            "* outputs {.val {names(x$outputs)}}{if (!is.null(x$total)) ' and their total' else ''}, {length(x$draw)} posterior draw{?s}",
            "")
  print_rounded(summary(x), 4)
  invisible(x)
}

as_scenario <- function(scenario, arg = rlang::caller_arg(scenario), call = rlang::caller_env()) {
  if (inherits(scenario, "bayesbem_simulator")) {
    return(scenario(scenario))
  }
  if (!inherits(scenario, "bayesbem_scenario")) {
    abort_bayesbem(c("{.arg {arg}} must be a scenario or a simulator, not {describe_value(scenario)}.",
                     i = "Make one with {.fn scenario}."),
                   "argument", call = call)
  }
  scenario
}

# The scenarios' simulators run at the same posterior draws (paired): a
# draw is kept only where every scenario's run succeeded. Returns the draws
# (Stan scale), their indices and each scenario's outputs (draws by periods).
scenario_runs <- function(fit, scenarios, ndraws, cache_dir, call = rlang::caller_env()) {
  check_count(ndraws, call = call)
  draws <- draw_parameters(fit, ndraws)
  outputs <- lapply(scenarios, function(s) {
    check_fit_simulator(fit, s$simulator, call)
    design <- scenario_design(s, draw_design(fit, s$simulator, draws), call)
    run_at_draws(s$simulator, design, cache_dir, call)
  })
  ok <- Reduce(`&`, lapply(outputs, function(m) stats::complete.cases(m)))
  list(draws = draws[ok], index = attr(draws, "index")[ok],
       simulated = lapply(outputs, function(m) m[ok, , drop = FALSE]))
}

# The calibration parameters of each draw in physical units, one row per
# draw, within the simulator's ranges (unscaling can pass a bound by
# rounding).
draw_design <- function(fit, simulator, draws) {
  data <- fit$data
  tf <- unscale_t(do.call(rbind, lapply(draws, `[[`, "tf")), data$scaling)
  range <- simulator$parameters[match(data$names$t, simulator$parameters$parameter), ]
  design <- as.data.frame(tf)
  names(design) <- data$names$t
  design[] <- lapply(seq_along(design), function(k) {
    pmin(pmax(design[[k]], range$min[k]), range$max[k])
  })
  design
}

# A scenario's changes applied to the draws' design: scaled parameters are
# multiplied (an uncalibrated one from its initial value), set ones replaced.
scenario_design <- function(scenario, design, call) {
  table <- scenario$simulator$parameters
  for (name in names(scenario$scale)) {
    base <- design[[name]] %||% rep(table$initial[table$parameter == name], nrow(design))
    design[[name]] <- base * scenario$scale[[name]]
  }
  for (name in names(scenario$set)) design[[name]] <- rep(scenario$set[[name]], nrow(design))
  check_scenario_range(scenario$simulator, design[c(names(scenario$scale), names(scenario$set))],
                       "change", call = call)
  design
}

# The simulator's outputs at each row of `design` (rows; NA rows for failed
# runs); when every run fails, an error with the simulator's reasons.
run_at_draws <- function(simulator, design, cache_dir, call) {
  out <- simulate_design(simulator, design, cache_dir = cache_dir)
  eta <- matrix(NA_real_, nrow(design), nrow(simulator$x))
  ok <- setdiff(seq_len(nrow(design)), attr(out, "failed")$run)
  if (length(ok) == 0L) abort_all_failed(attr(out, "failed"), call)
  eta[ok, ] <- matrix(out$eta, nrow = length(ok), byrow = TRUE)
  eta
}

# The simulator must take the fit's calibration parameters and report its
# observable inputs.
check_fit_simulator <- function(fit, simulator, call) {
  check_simulator(simulator, call = call)
  data <- fit$data
  unknown <- setdiff(data$names$t, simulator$parameters$parameter)
  missing_x <- setdiff(data$names$x, names(simulator$x))
  if (length(unknown) > 0L || length(missing_x) > 0L) {
    abort_bayesbem(c("{.arg simulator} does not match the fit.",
                     x = if (length(unknown) > 0L) "It has no parameter{?s} {.field {unknown}}.",
                     x = if (length(missing_x) > 0L) "It has no observable input{?s} {.field {missing_x}}.",
                     i = "Use the simulator whose runs the fit was calibrated on."),
                   "simulator", call = call)
  }
}

# The scenario's observable inputs with the covariates of the fit's
# discrepancy terms, when it has any.
scenario_inputs <- function(fit, scenario, covariates, call = rlang::caller_env()) {
  x <- scenario$simulator$x
  if (is.null(covariates)) {
    return(x)
  }
  covariates <- as_numeric_table(covariates, "covariates", call = call)
  if (nrow(covariates) != nrow(x)) {
    abort_bayesbem(c("{.arg covariates} must have one row per period of the scenario ({nrow(x)}).",
                     x = "It has {nrow(covariates)}."),
                   "covariates", call = call)
  }
  cbind(x, covariates[setdiff(names(covariates), names(x))])
}

# The discrepancy at the scenario's inputs, one draw per row of `simulated`
# (physical units): for each posterior draw, delta given the data and
# eta = the simulator's output there (delta_given_eta()), plus the
# parametric terms of extend().
scenario_delta <- function(fit, inputs, simulated, draws) {
  data <- fit$data
  x <- withCallingHandlers(
    scale_newdata(data, inputs, arg = "scenario"),
    bayesbem_warning_extrapolation = function(w) {
      warn_bayesbem(c("The scenario's weather lies outside the weather the model was calibrated on.",
                      i = "The simulator runs there; the discrepancy extrapolates, towards its mean."),
                    "extrapolation")
      invokeRestart("muffleWarning")
    })
  g <- gp_geometry(data, x, fit_structure(fit))
  s <- scale_y(simulated, data$scaling)
  delta <- t(vapply(seq_along(draws), function(i) {
    delta_given_eta(koh_conditional(g, draws[[i]]), s[i, ])
  }, numeric(ncol(s))))
  delta <- matrix(delta, nrow = length(draws))
  if (length(data$covariates) > 0L) {
    gamma <- do.call(rbind, lapply(draws, `[[`, "gamma"))
    delta <- delta + gamma %*% t(scale_covariates(data, inputs))
  }
  unscale_y_spread(delta, data$scaling)
}

# One draw of delta from the joint Gaussian (eta, delta) of
# koh_conditional() given eta = s: mean m_d + C_de C_ee^-1 (s - m_e),
# covariance C_dd - C_de C_ee^-1 C_ed. The gain C_de C_ee^-1 stays bounded
# where the runs pin eta down (it tends to -P_dd^-1 P_de of the precision),
# so a floor of 1e-10 of the largest variance on C_ee's diagonal only
# guards rounding.
delta_given_eta <- function(cond, s) {
  n <- length(s)
  e <- seq_len(n)
  d <- n + e
  c_ee <- cond$cov[e, e, drop = FALSE]
  diag(c_ee) <- diag(c_ee) + 1e-10 * max(diag(c_ee), .Machine$double.xmin)
  r <- jittered_chol(c_ee)
  k <- backsolve(r, t(cond$cov[d, e, drop = FALSE]), transpose = TRUE)
  w <- backsolve(r, s - cond$mean[e], transpose = TRUE)
  rmvnorm_psd(cond$mean[d] + drop(crossprod(k, w)),
              cond$cov[d, d, drop = FALSE] - crossprod(k))
}

# Observation noise N(0, 1/lambda_e) of each draw, physical units.
noise_draws <- function(fit, draws, n) {
  sd_e <- fit$data$scaling$y_scale / sqrt(vapply(draws, `[[`, numeric(1), "lambda_e"))
  matrix(stats::rnorm(length(draws) * n, sd = sd_e), length(draws), n)
}
