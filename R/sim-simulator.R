#' Simulators
#'
#' A simulator turns one setting of the uncertain parameters (physical units)
#' into the simulated output of every field period, and knows the observable
#' inputs `x` of those periods. `simulator()` wraps any R function;
#' [bem_simulator()] is the package's embedded building model.
#'
#' @param fun A function `fun(params, x)` taking a named list of all
#'   parameters (one value each, physical units) and the data frame `x`, and
#'   returning a numeric vector with one output per row of `x`, or, for a
#'   simulator of several outputs (meters), a data frame with one named
#'   column per output and one row per row of `x` ([simulate_design()] then
#'   writes the long table with an `output` column that [koh_data()] takes).
#'   With `weather`, `fun(params, x, days)`: `days` is the daily weather of
#'   the periods (see `weather`).
#' @param x A data frame of the observable inputs of each field period.
#' @param parameters A parameter table (see [bem_parameters()]): every
#'   parameter `fun` takes, with its initial value and range. Parameters a
#'   design does not vary are held at their initial values.
#' @param name A short description, for printing.
#' @param key Anything else the output depends on, for the cache of
#'   [simulate_design()]: runs are cached under a hash of this key, the
#'   code of `fun`, the values (at the time of the runs) of the variables
#'   `fun` uses from outside (not environments), the inputs `x` and the
#'   parameter values. Give e.g. the contents of files `fun` reads.
#' @param periods Optional: when each row of `x` is, a data frame with
#'   `start` and `end` (`Date`s, the first and last day, or for hours
#'   `POSIXct`s, the hour's start and the next's); [field_hours()] matches
#'   a meter's timestamps to them. The weather-driven simulators set it.
#'   Periods backwards, out of order or overlapping are an error of class
#'   `bayesbem_error_periods` naming the rows, as in [epw_weather()].
#' @param weather Optional, with `periods` of days (e.g. bills on their own
#'   dates): the path of an EPW file whose days `fun` receives as its third
#'   argument, `days`: [epw_weather()]'s daily table of the days the
#'   periods hold, with `period`, the row of `x` each belongs to. A model
#'   that acts day by day (heating degree-days from each day's mean
#'   temperature) needs the days, not the periods' means.
#' @return An object of class `bayesbem_simulator`.
#' @family simulation
#' @export
#' @examples
#' lin <- simulator(function(params, x) params$a * x$temp + params$b,
#'                  x = data.frame(temp = c(0, 10, 20)),
#'                  parameters = data.frame(parameter = c("a", "b"), initial = c(1, 0),
#'                                          min = c(0, -5), max = c(2, 5)))
#' lin
#' simulate_design(lin, data.frame(a = c(0.5, 1.5)))
#'
#' # a heating degree-day model of bills on their own dates, day by day
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' bills <- data.frame(start = as.Date(c("2013-01-05", "2013-02-04", "2013-03-06")),
#'                     end = as.Date(c("2013-02-03", "2013-03-05", "2013-04-03")))
#' degree_days <- function(params, x, days) {
#'   heating <- params$ua * pmax(params$base - days$temp, 0) * 24 / 1000
#'   as.vector(tapply(heating, days$period, sum)) + params$base_load * x$days
#' }
#' hdd <- simulator(degree_days, epw_weather(epw, periods = bills)[c("temp", "days")],
#'                  data.frame(parameter = c("ua", "base", "base_load"),
#'                             initial = c(200, 15, 20), min = c(50, 10, 5),
#'                             max = c(400, 20, 40)),
#'                  periods = bills, weather = epw)
#' simulate_design(hdd, data.frame(ua = c(100, 300)))
simulator <- function(fun, x, parameters, name = "custom simulator", key = NULL,
                      periods = NULL, weather = NULL) {
  if (!is.function(fun)) {
    abort_bayesbem("{.arg fun} must be a function {.code fun(params, x)}.", "argument")
  }
  x <- as_numeric_table(x)
  if (!is.null(periods)) periods <- check_simulator_periods(periods, nrow(x))
  if (!is.null(weather)) fun <- with_period_days(fun, periods, weather)
  new_simulator(fun, x, parameters, name, key, periods)
}

# `fun(params, x, days)` as a simulator's `fun(params, x)`: the days of a
# weather file the periods hold (each with its `period`, the row of `x`).
with_period_days <- function(fun, periods, weather, call = rlang::caller_env()) {
  if (is.null(periods) || !inherits(periods$start, "Date")) {
    abort_bayesbem(c("{.arg weather} needs {.arg periods} of days: each row's first and last day.",
                     i = "E.g. {.code periods = bills}, a table of {.cls Date}s {.field start} and {.field end}."),
                   "periods", call = call)
  }
  if (length(formals(fun)) < 3L && !"..." %in% names(formals(fun))) {
    abort_bayesbem("With {.arg weather}, {.arg fun} must take the days as a third argument: {.code fun(params, x, days)}.",
                   "argument", call = call)
  }
  days <- epw_weather(weather, by = "day")
  ymd <- data.frame(year = as.integer(format(days$date, "%Y")),
                    month = as.integer(format(days$date, "%m")),
                    day = as.integer(format(days$date, "%d")))
  period <- period_of_days(ymd, periods, weather, call)
  days <- days[!is.na(period), setdiff(names(days), "end"), drop = FALSE]
  days$period <- period[!is.na(period)]
  rownames(days) <- NULL
  function(params, x) fun(params, x, days)
}

# A simulator whose periods are those of its weather file, already checked
# (a typical year's months come from several years, so they are in the
# file's order rather than the calendar's).
new_simulator <- function(fun, x, parameters, name, key, periods, call = rlang::caller_env()) {
  x <- as_numeric_table(x, "x", call = call)
  check_numeric_complete(x, names(x), "x", call = call)
  structure(list(fun = fun, x = x, parameters = check_parameter_table(parameters), name = name,
                 key = key, periods = periods),
            class = "bayesbem_simulator")
}

# The periods of a weather table (epw_weather()'s `date` and `end`, or by
# hour its `time` and the next hour), NULL for a table without them.
weather_periods <- function(weather) {
  if (!is.null(weather$time)) {
    return(data.frame(start = weather$time, end = weather$time + 3600))
  }
  if (all(c("date", "end") %in% names(weather))) data.frame(start = weather$date, end = weather$end)
}

# What determines a simulator's output besides the inputs and parameters:
# its `key`, its function's code (as text: source references hold file
# times) and the current values of the variables that code uses but does not
# define (found by codetools), wherever they live. Functions among those
# values count by their code; environments (mutable state such as counters)
# are left out.
simulator_key <- function(sim) {
  fun <- sim$fun
  used <- codetools::findGlobals(fun, merge = FALSE)$variables
  values <- mget(used, envir = environment(fun), inherits = TRUE,
                 ifnotfound = rep(list(NULL), length(used)))
  values <- Filter(Negate(is.environment), values)
  list(sim$key, deparse(fun), lapply(values, key_value))
}

# A value as the cache key sees it: functions by their code, also inside
# lists (e.g. a list of measures).
key_value <- function(v) {
  if (is.function(v)) deparse(v) else if (is.list(v) && !is.object(v)) lapply(v, key_value) else v
}

#' @export
print.bayesbem_simulator <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_simulator}: {x$name}",
            "* {nrow(x$x)} period{?s}; observable inputs {.field {names(x$x)}}",
            "* {nrow(x$parameters)} parameter{?s}: {.field {x$parameters$parameter}}")
  invisible(x)
}

#' One output of a simulator of several
#'
#' A simulator of several outputs (meters) gives every output from one run.
#' The tools that rerun a simulator for one fit ([validate_emulator()],
#' [predict_scenario()], [savings()], [avoided_energy()],
#' [posterior_simulate()]) take one output; `output_simulator()` gives the
#' simulator of one, to use with that output's fit ([output_fit()]).
#'
#' @param simulator A `bayesbem_simulator` whose runs return several
#'   outputs.
#' @param output The output's name.
#' @return A `bayesbem_simulator` returning that output alone. Each run
#'   still computes every output; the cache of [simulate_design()] keys its
#'   runs by the simulator as it is when `output_simulator()` is called and
#'   the output.
#' @family simulation
#' @export
#' @examples
#' both <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"),
#'                       output = c("electricity", "gas"))
#' gas <- output_simulator(both, "gas")
#' simulate_design(gas, data.frame(infiltration_per_exterior_area = 0.001))
output_simulator <- function(simulator, output) {
  if (!inherits(simulator, "bayesbem_simulator")) {
    abort_bayesbem(c("{.arg simulator} must be a simulator, not {.obj_type_friendly {simulator}}.",
                     i = "Make one with {.fn simulator}, {.fn bem_simulator} or {.fn eplus_simulator}."),
                   "argument")
  }
  if (!rlang::is_string(output)) {
    abort_bayesbem("{.arg output} must be an output's name, not {describe_value(output)}.",
                   "argument")
  }
  fun <- simulator$fun
  one <- function(params, x) {
    values <- fun(params, x)
    if (!is.data.frame(values) || !output %in% names(values)) {
      stop(sprintf("the simulator gave no output \"%s\" (it gave %s)", output,
                   if (is.data.frame(values)) paste(names(values), collapse = ", ") else "one output"),
           call. = FALSE)
    }
    values[[output]]
  }
  # (the periods of meters read on other days overlap: each meter runs over all)
  new_simulator(one, simulator$x, simulator$parameters, name = paste0(simulator$name, ": ", output),
                key = list(simulator_key(simulator), output), periods = simulator$periods)
}

#' The embedded building model as a simulator
#'
#' The default simulator of the package: [bem_monthly()] driven by the
#' monthly means of an EPW weather file, so that screening, design and
#' calibration run without external software. Its observable inputs are the
#' monthly mean dry-bulb temperature `temp`, relative humidity `rh` and
#' direct normal radiation `solar`, as in [seb_field].
#'
#' By week, day or hour it is the hourly model ([bem_hourly()], the same
#' building and parameters) over the weather file, summed into weeks or
#' days, or hour by hour: interval data without EnergyPlus. Its inputs are
#' then the periods' mean weather, and by day also the `weekday` (1
#' Monday to 7 Sunday), by hour the `weekday` and the `daytype_hour` (the
#' hour, 0-23, on weekdays, the hour plus 24 on weekends): the schedules
#' act by hour of the week, and an additive discrepancy (large hourly
#' data, see [calibrate()]) needs the hour per day type to hold a load
#' that only weekends' or only weekdays' hours have.
#'
#' With `periods` (e.g. bills on their own dates, see [epw_weather()]) the
#' model runs once per period, at the period's mean weather over its hours:
#' the quasi-steady method holds for periods of a few weeks as for months.
#' When the periods differ in length, their number of days is an observable
#' input too (`days`): the emulator then learns that a longer bill holds
#' more use.
#'
#' @param weather Monthly weather from [epw_monthly()], or the path of an EPW
#'   file. Several years can be stacked with `rbind()`.
#' @param by With `weather` an EPW file: `"month"` (the monthly model) or
#'   `"week"`, `"day"`, `"hour"`: the hourly model ([bem_hourly()]) over
#'   the whole file, summed into weeks or days or hour by hour.
#' @param periods With `weather` an EPW file: the measurements' own periods,
#'   a data frame with columns `start` and `end` (see [epw_weather()]), or
#'   for several meters read on other days a list of such tables named by
#'   output (every meter is then simulated over all the periods; each
#'   output's field rows pick their own).
#' @param parameters A parameter table (default [bem_parameters()]) with
#'   every parameter of the embedded model; to vary only some, give those
#'   to [design_lhs()].
#' @param building Building properties from [bem_building()].
#' @param output `"electricity"`, `"gas"` (kWh per period) or both,
#'   `c("electricity", "gas")`: a simulator of both meters, from one run of
#'   the model.
#' @return A `bayesbem_simulator`.
#' @family simulation
#' @export
#' @examples
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' sim
#' simulate_design(sim, data.frame(equipment_power_density = c(10, 20)))
bem_simulator <- function(weather, parameters = bem_parameters(), building = bem_building(),
                          output = "electricity", by = c("month", "week", "day", "hour"),
                          periods = NULL) {
  check_by_or_periods(by, periods)
  by <- match_choice(by)
  missing <- setdiff(bem_parameters()$parameter, check_parameter_table(parameters)$parameter)
  if (length(missing) > 0L) {
    abort_bayesbem(c("{.arg parameters} lacks {length(missing)} parameter{?s} of the embedded model: {.field {missing}}.",
                     i = "Give the whole table (e.g. {.code bem_parameters(type = )}) and the parameters to vary to {.fn design_lhs}."),
                   "argument")
  }
  meters <- c("electricity", "gas")
  if (!is.character(output) || length(output) == 0L || anyNA(output) || anyDuplicated(output)) {
    abort_bayesbem("{.arg output} must be {.val electricity}, {.val gas} or both, not {describe_value(output)}.",
                   "argument")
  }
  unknown <- setdiff(output, meters)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg output} names {.val {unknown}}, not a meter of the embedded model.",
                     i = "Its meters: {.val {meters}}."),
                   "argument")
  }
  if ((!is.null(periods) || by != "month") && !is.character(weather)) {
    abort_bayesbem(c("With {.arg periods} or {.arg by}, {.arg weather} must be the path of an EPW file.",
                     i = "The periods' weather is summarised from its hours."),
                   "argument")
  }
  if (!is.null(periods)) periods <- check_output_periods(periods, output)
  if (by %in% c("week", "day", "hour")) {
    return(bem_hourly_simulator(weather, parameters, building, output, by))
  }
  if (is.character(weather)) {
    weather <- if (is.null(periods)) epw_monthly(weather) else
      periods_weather(read_epw_hourly(weather), periods, weather)
  }
  x <- weather_inputs(weather, !is.null(periods))
  fun <- function(params, x) bem_monthly(params, weather, building)[output]
  new_simulator(one_or_outputs(fun, output), x, parameters,
                name = paste0("embedded monthly building model, ", paste(output, collapse = " and "),
                              " (kWh)"),
                key = list(weather, building, output), periods = weather_periods(weather))
}

# bem_simulator() by week, day or hour: the hourly model over the whole
# weather file, summed into the periods; its inputs are the periods' mean
# weather and, by day, the weekday, by hour the hour and the weekday (the
# schedules act by hour of week).
bem_hourly_simulator <- function(path, parameters, building, output, by) {
  records <- read_epw_hourly(path)
  hourly <- hourly_weather(records, path)
  if (by == "hour") {
    period <- seq_len(nrow(records))
    # the inputs' weekday and hour are the schedules' (the building's clock)
    weather <- utils::modifyList(hourly, schedule_calendar(hourly, building))
  } else {
    period <- record_periods(records, record_days(records), by)
    weather <- summarise_epw(records, by, path = path)
    weather$weekday <- hourly$weekday[!duplicated(period)]
  }
  x <- interval_inputs(weather, by)
  fun <- function(params, x) {
    out <- bem_hourly(params, hourly, building)[output]
    if (by == "hour") out else as.data.frame(lapply(out, function(v) as.vector(tapply(v, period, sum))))
  }
  new_simulator(one_or_outputs(fun, output), x, parameters,
                name = sprintf("embedded hourly building model by %s, %s (kWh)", by,
                               paste(output, collapse = " and ")),
                key = list(hourly, building, output, by), periods = weather_periods(weather))
}

# The inputs of a simulator by week, day or hour: the periods' mean
# weather, by day also the weekday, by hour the weekday and the hour of the
# day type (0-23 on weekdays, 24-47 on weekends) in place of the hour: it
# lets a discrepancy additive over the inputs (gp-hsgp.R) hold an effect
# of the hour on weekends alone (a weekend plug load), which a sum of a
# weekday and an hour effect cannot (the parameters took it up), and the
# hour beside it would only add cost
# (inst/notes/decisions/S10-an-hour-profile-per-day-type.md).
interval_inputs <- function(weather, by) {
  x <- weather_inputs(weather, FALSE)
  if (by %in% c("day", "hour")) x$weekday <- weather$weekday
  if (by == "hour") x$daytype_hour <- weather$hour + 24L * (weather$weekday >= 6L)
  x
}

# A simulator function of the meters `output`: the vector of one, the data
# frame of several.
one_or_outputs <- function(fun, output) {
  if (length(output) > 1L) fun else function(params, x) fun(params, x)[[1]]
}

# A simulator's observable inputs from its weather table: the means
# `temp`, `rh` and `solar`, and with the data's own `periods` their `days`
# when they differ in length.
weather_inputs <- function(weather, periods) {
  x <- data.frame(temp = weather$temp, rh = weather$rh, solar = weather$dni)
  if (periods && length(unique(weather$days)) > 1L) x$days <- weather$days
  x
}

check_parameter_table <- function(parameters, arg = rlang::caller_arg(parameters),
                                  call = rlang::caller_env()) {
  needed <- c("parameter", "initial", "min", "max")
  if (!is.data.frame(parameters) || !all(needed %in% names(parameters))) {
    abort_bayesbem(c("{.arg {arg}} must be a parameter table with columns {.field {needed}}.",
                     i = "See {.fn bem_parameters} for an example."),
                   "parameters", call = call)
  }
  check_numeric_complete(parameters, needed[-1], arg, call = call)
  bad <- parameters$parameter[!(parameters$min < parameters$max) |
                                parameters$initial < parameters$min |
                                parameters$initial > parameters$max]
  if (length(bad) > 0L) {
    abort_bayesbem(c("{.field {bad}}: each parameter needs {.code min < max} and an initial value within them.",
                     i = "Fix the ranges in {.arg {arg}}."),
                   "parameters", call = call)
  }
  if (anyDuplicated(parameters$parameter)) {
    abort_bayesbem("{.arg {arg}} names a parameter more than once.", "parameters", call = call)
  }
  parameters
}

# Every parameter of a parameter table at its initial value, by name.
initial_values <- function(parameters) {
  stats::setNames(as.list(parameters$initial), parameters$parameter)
}

# Full parameter lists for each row of `design`: the design's values, and the
# initial value of every parameter the design does not vary.
design_settings <- function(sim, design, call = rlang::caller_env()) {
  design <- as_numeric_table(design, "design", call = call)
  table <- sim$parameters
  unknown <- setdiff(names(design), table$parameter)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg design} has column{?s} {.field {unknown}}, not parameter{?s} of the simulator.",
                     i = "Its parameters are {.field {table$parameter}}."),
                   "columns", call = call)
  }
  check_numeric_complete(design, names(design), "design", call = call)
  range <- table[match(names(design), table$parameter), ]
  outside <- names(design)[vapply(seq_along(design), function(k) {
    any(design[[k]] < range$min[k] | design[[k]] > range$max[k])
  }, logical(1))]
  if (length(outside) > 0L) {
    abort_bayesbem(c("{.arg design} has values outside the parameter range of {.field {outside}}.",
                     i = "Keep each parameter within its {.field min} and {.field max}."),
                   "parameters", call = call)
  }
  base <- initial_values(table)
  lapply(seq_len(nrow(design)), function(i) utils::modifyList(base, as.list(design[i, , drop = FALSE])))
}

check_simulator <- function(simulator, arg = rlang::caller_arg(simulator),
                            call = rlang::caller_env()) {
  if (!inherits(simulator, "bayesbem_simulator")) {
    abort_bayesbem(c("{.arg {arg}} must be a simulator, not {describe_value(simulator)}.",
                     i = "Make one with {.fn simulator}, {.fn bem_simulator} or {.fn eplus_simulator}."),
                   "argument", call = call)
  }
}

#' An hourly simulator with the heat its building stored as an input
#'
#' Two hours of an hourly simulator with the same weather, hour and weekday
#' (two calm nights) share their inputs, though the building behind them
#' may differ: the heat its mass stored in the hours before. The emulator
#' takes the simulator as a function of its inputs and averages such hours
#' (a message of [koh_data()] says by how much they differed), and the
#' discrepancy cannot tell them apart. `with_lagged_temperature()` adds the
#' input that carries that state: `temp_lag`, the mean outdoor temperature
#' of the `hours` hours before each hour (of the hours there are, at the
#' start of the file).
#'
#' @param simulator A simulator by hour (e.g. `bem_simulator(epw, by =
#'   "hour")` or `eplus_simulator(..., by = "hour")`).
#' @param hours How many hours before each hour to average.
#' @return The simulator, its inputs `x` with the column `temp_lag`.
#' @family simulation
#' @export
#' @examples
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"),
#'                      by = "hour")
#' head(with_lagged_temperature(sim)$x)
with_lagged_temperature <- function(simulator, hours = 24L) {
  check_simulator(simulator)
  check_count(hours)
  start <- simulator$periods$start
  if (!inherits(start, "POSIXct") || is.null(simulator$x$temp) ||
      any(diff(as.numeric(start)) != 3600)) {
    abort_bayesbem(c("{.arg simulator} must simulate consecutive hours with a {.field temp} input.",
                     i = "Make it with {.code by = \"hour\"}, e.g. {.code bem_simulator(epw, by = \"hour\")}."),
                   "argument")
  }
  temp <- simulator$x$temp
  # the sum of the `hours` temperatures before each hour, from cumulative sums
  total <- c(0, cumsum(temp))
  n <- length(temp)
  from <- pmax(seq_len(n) - hours, 1L)
  counts <- seq_len(n) - from
  lagged <- ifelse(counts > 0, (total[seq_len(n)] - total[from]) / pmax(counts, 1), temp)
  simulator$x$temp_lag <- lagged
  simulator$name <- sprintf("%s, with the previous %d hours' mean temperature", simulator$name,
                            hours)
  simulator
}
