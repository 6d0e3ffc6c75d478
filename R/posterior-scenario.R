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
#' @template args-covariates-scenario
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
#'   `scenario`. `summary(x, level)` gives per period and in total the
#'   mean, sd, median and the bounds of the central `level` interval (order
#'   statistics of the draws, as `predict()`'s).
#' @family prediction
#' @export
#' @examples
#' \donttest{
#' # seb_fit's runs are EnergyPlus's; the embedded model stands in here
#' sim_2012 <- bem_simulator(system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem"))
#' p <- predict_scenario(seb_fit, sim_2012, ndraws = 20)
#' p
#' summary(p)
#' }
predict_scenario <- function(fit, scenario, ndraws = 40,
                             discrepancy = c("same", "proportional", "none"), noise = TRUE,
                             covariates = NULL, cache_dir = NULL, total = NULL, ...) {
  rlang::check_dots_empty()
  match_choice(discrepancy)
  check_fit(fit)
  as_scenario(scenario)
  check_bool(noise)
  UseMethod("predict_scenario")
}

#' @export
predict_scenario.bayesbem_fit <- function(fit, scenario, ndraws = 40,
                                          discrepancy = c("same", "proportional", "none"),
                                          noise = TRUE, covariates = NULL, cache_dir = NULL,
                                          total = NULL, ...) {
  discrepancy <- match_choice(discrepancy)
  check_no_total(total)
  scenario <- as_scenario(scenario)
  changed <- length(scenario$set) + length(scenario$scale) > 0L
  scenarios <- list(scenario)
  if (discrepancy == "proportional" && changed) {
    scenarios$calibrated <- as_scenario(scenario$simulator)
  }
  inputs <- scenario_inputs(fit, scenario, covariates)
  runs <- scenario_runs(fit, scenarios, ndraws, cache_dir)
  simulated <- runs$simulated[[1]]
  given <- if (discrepancy != "none") {
    scenario_delta(fit, inputs, runs$simulated[[length(scenarios)]], runs$draws)
  }
  delta <- switch(discrepancy, none = 0 * simulated, same = given$delta,
                  proportional = given$delta * simulated / runs$simulated[[length(scenarios)]])
  y <- simulated + delta
  if (noise) {
    y <- y + noise_draws(fit, runs$draws, scenario$simulator$x, scenario$simulator$periods$start,
                         known = given$shift)
  }
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
#' @export
predict_scenario.bayesbem_fit_outputs <- function(fit, scenario, ndraws = 40,
                                                  discrepancy = c("same", "proportional", "none"),
                                                  noise = TRUE, covariates = NULL,
                                                  cache_dir = NULL, total = NULL, ...) {
  call <- rlang::current_env()
  discrepancy <- match_choice(discrepancy)
  scenario <- as_scenario(scenario)
  check_output_covariates(covariates, names(fit$outputs), call)
  preds <- each_output_runs(fit, list(scenario), function(k, one, scenario) {
    predict_scenario(one, scenario, ndraws = ndraws, discrepancy = discrepancy, noise = noise,
                     covariates = covariates[[k]], cache_dir = cache_dir)
  }, call = call)
  draw <- lapply(preds, `[[`, "draw")
  y_total <- if (!is.null(total)) {
    check_total_weights(total, lapply(preds, `[[`, "inputs"), call = call)
    weighted_total(total, lapply(preds, `[[`, "y"), draw)
  }
  structure(list(outputs = preds, total = y_total, weights = total, draw = Reduce(intersect, draw),
                 scenario = scenario),
            class = "bayesbem_scenario_predictions")
}

#' @export
summary.bayesbem_scenario_predictions <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  tables <- lapply(object$outputs, summary, level = level)
  if (!is.null(object$total)) {
    inputs <- object$outputs[[names(object$weights)[1]]]$inputs
    tables$total <- draws_with_total(object$total, inputs, level)
  }
  stack_outputs(tables)
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
