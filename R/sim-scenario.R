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
