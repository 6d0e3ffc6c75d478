#' EnergyPlus as a simulator
#'
#' Wraps an EnergyPlus model as a simulator: each run sets the fields the
#' parameter map names and applies the measures, runs EnergyPlus on the
#' weather file (see [eplus_run()]) and returns one output per field period:
#' a meter or output variable reported daily, over the weather-file run
#' period only, summed over each period (energy, in kWh) or averaged
#' (temperatures, rates). The periods are the weather's months, weeks or
#' days (`by`, as in [epw_weather()]), and the observable inputs `temp`,
#' `rh` and `solar` are that weather's means over them, as in [seb_field].
#'
#' The map ([eplus_parameter_map()]) has one row per field a parameter sets:
#' `parameter`, `object_type`, `object_name` (or a wildcard: `"*"` for every
#' object of the class, `"Office*"` for those whose names match, listed in a
#' message), `field` (its name in the IDD,
#' any case, or its epJSON key) and `apply`: `"value"` sets the field to the
#' parameter's value, `"multiply"` to the original value times it (e.g. a
#' density multiplier), `"divide"` to the original value divided by it (an
#' R-value multiplier acting on conductivity). A field that acts only under
#' a calculation method (e.g. `Watts per Floor Area` of `Lights` under
#' `Watts/Area`) is set together with its method when `apply` is `"value"`
#' and refused otherwise. What a field cannot express goes in a measure, as
#' eplusr calls it: `measures` is a named list of functions
#' `function(model, value)` returning the model edited for the named
#' parameter's value (with [eplus_set()], [eplus_add()]); such parameters
#' need a row in `parameters`. When the simulator is made, EnergyPlus checks
#' every mapped field at both ends of the parameter ranges.
#'
#' The model must be of the installed EnergyPlus's version. Missing outputs
#' are added (the daily meter or variable, `Output:SQLite`). A run that
#' fails or takes longer than `timeout` seconds is an error of class
#' `bayesbem_error_eplus_run` quoting EnergyPlus's severe and fatal
#' messages; [simulate_design()] keeps such runs apart. Runs are cached (with
#' `cache_dir`) under a key covering the model, the weather, the map, the
#' measures, the files the model reads and the parameter values.
#'
#' @param model An EnergyPlus model from [eplus_model()], or the path of
#'   one (`.idf`, `.epJSON`). Defaults to the shipped case-study building
#'   (EnergyPlus 25.2).
#' @param weather Path of the EPW weather file (or `.epw.gz`).
#' @param parameters A parameter table (see [bem_parameters()]); by default
#'   the parameters of the map, with their ranges.
#' @param map The parameter map (see Details), or `NULL` when only measures
#'   set parameters.
#' @param measures A named list of functions `function(model, value)`.
#' @param output Name of a meter (`"Electricity:Facility"`,
#'   `"NaturalGas:Facility"`) or output variable (`"Zone Mean Air
#'   Temperature"`), or several: one run then gives every one of them, each
#'   an output of its own (named as given) for a calibration on several
#'   outputs (see [koh_data()]).
#' @param key For an output variable reported for several objects, which one
#'   (e.g. a zone name).
#' @param by Field periods: `"month"`, `"week"`, `"day"` or `"hour"` (the
#'   model's hourly output as EnergyPlus reports it, each hour stamped by
#'   its end as the weather's records are; the inputs as
#'   [bem_simulator()]'s by hour).
#' @param periods Instead of `by`, the measurements' own periods (e.g.
#'   bills), a data frame with columns `start` and `end` (see
#'   [epw_weather()]), or for several meters read on other days a list of
#'   such tables named by output (every meter is then simulated over all
#'   the periods, and each output's field rows pick their own); the daily
#'   output is summed over each, and when they differ in length their
#'   `days` is an observable input too.
#' @param timeout Time limit of each run, in seconds (whole seconds, rounded up).
#' @param eplus Directory of EnergyPlus, see [eplus_path()].
#' @return A `bayesbem_simulator`.
#' @family EnergyPlus
#' @family simulation
#' @export
#' @examples
#' \donttest{
#' if (eplus_available()) {
#'   sim <- eplus_simulator(weather = system.file("extdata", "2013_AMY.epw.gz",
#'                                                package = "bayesbem"))
#'   simulate_design(sim, data.frame(equipment_power_density = c(10, 20)))
#' }
#' }
eplus_simulator <- function(model = system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"),
                            weather, parameters = NULL, map = eplus_parameter_map(),
                            measures = list(), output = "Electricity:Facility", key = NULL,
                            by = c("month", "week", "day", "hour"), periods = NULL, timeout = 600,
                            eplus = NULL) {
  check_by_or_periods(by, periods)
  by <- match_choice(by)
  check_eplus_outputs(output)
  if (!is.null(periods)) periods <- check_output_periods(periods, output)
  eplus <- eplus_path(eplus)
  check_file(weather, "weather")
  check_number(timeout, "argument", positive = TRUE)
  if (!inherits(model, "bayesbem_eplus_model")) model <- eplus_model(model, eplus)
  map <- if (is.null(map)) empty_map() else check_parameter_map(map, model)
  parameters <- check_parameter_table(parameters %||% map_parameters(map))
  check_measures(measures, parameters)
  unset <- setdiff(parameters$parameter, c(map$parameter, names(measures)))
  if (length(unset) > 0L) {
    abort_bayesbem(c("{.arg parameters} has {.field {unset}}, which neither {.arg map} nor {.arg measures} sets.",
                     i = "Add rows for {.field {unset}} to {.arg map}, or a measure."),
                   "parameters")
  }
  frequency <- if (by == "hour") "Hourly" else "Daily"
  model <- with_sqlite(Reduce(function(m, o) with_output(m, o, frequency), output, model))
  for (end in c("min", "max")) {
    at <- stats::setNames(as.list(parameters[[end]]), parameters$parameter)
    check_model_fields(apply_parameters(model, map, measures, at), eplus)
  }
  hourly <- read_epw_hourly(weather)
  model <- weather_run_years(model, hourly)
  if (by == "hour") {
    summary <- hourly_weather(hourly, weather)
    x <- interval_inputs(summary, by)
  } else {
    days <- weather_days(hourly, by)
    members <- period_members(days, periods, weather)
    summary <- if (is.null(periods)) summarise_epw(hourly, by, path = weather) else
      periods_weather(hourly, periods, weather)
    x <- weather_inputs(summary, !is.null(periods))
  }
  fun <- function(params, x) {
    dir <- tempfile("eplus-run-")
    on.exit(unlink(dir, recursive = TRUE), add = TRUE)
    run <- run_model(apply_parameters(model, map, measures, params), weather, eplus, dir, timeout)
    values <- lapply(output, function(o) {
      if (by == "hour") hourly_values(eplus_output(run, o, key, by = "hour"), hourly) else
        aggregate_daily(eplus_output(run, o, key), days, members)
    })
    if (length(output) == 1L) values[[1]] else
      as.data.frame(stats::setNames(values, output), check.names = FALSE)
  }
  name <- sprintf("EnergyPlus %s: %s, %s by %s", model$version, basename(model$source),
                  paste(output, collapse = " and "),
                  if (is.null(periods)) by else sprintf("%d periods of the data", nrow(union_periods(periods))))
  new_simulator(fun, x, parameters, name = name,
                key = list(unname(tools::md5sum(weather)), model_files_md5(model)),
                periods = weather_periods(summary))
}

# `output` names one or more meters or output variables, each once.
check_eplus_outputs <- function(output, call = rlang::caller_env()) {
  if (!is.character(output) || length(output) == 0L || anyNA(output) || any(!nzchar(output))) {
    abort_bayesbem("{.arg output} must name meters or output variables, not {describe_value(output)}.",
                   "argument", call = call)
  }
  if (anyDuplicated(tolower(output))) {
    abort_bayesbem("{.arg output} names {.val {output[duplicated(tolower(output))]}} more than once.",
                   "argument", call = call)
  }
}

empty_map <- function() {
  data.frame(parameter = character(), object_type = character(), object_name = character(),
             field = character(), apply = character(), original = numeric(),
             method_field = character(), method_value = character())
}

# The contents of the files a model reads (Schedule:File and the like), so
# that the cache sees a changed schedule file.
model_files_md5 <- function(model) {
  files <- as.character(unlist(lapply(model$json, function(objects) {
    lapply(objects, function(o) if (is.character(o$file_name)) o$file_name)
  })))
  files <- files[file.exists(files)]
  unname(tools::md5sum(files))
}
