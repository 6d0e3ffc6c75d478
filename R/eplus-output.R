#' Results of an EnergyPlus run
#'
#' Reads one meter or output variable of a run from its SQLite output
#' (`eplusout.sql`, through DBI/RSQLite), over the weather-file run period
#' only: sizing periods and design days never count. Energy in joules is
#' returned in kWh.
#'
#' @param run A `bayesbem_eplus_run` from [eplus_run()].
#' @param name The meter (e.g. `"Electricity:Facility"`) or output variable
#'   (e.g. `"Zone Mean Air Temperature"`), any case.
#' @param key For an output variable reported for several objects, the
#'   object (e.g. the zone `"ZONE ONE"`).
#' @param by The reporting frequency: `"day"`, `"hour"`, `"month"`,
#'   `"timestep"` or `"run period"` (EnergyPlus's Daily, Hourly, Monthly,
#'   Timestep, RunPeriod).
#' @return A data frame with one row per reported interval: `month`, `day`,
#'   `hour`, `minute` (the end of the interval), `value`; attributes `type`
#'   (`"Sum"` for energy, `"Avg"` for rates and temperatures) and `units`.
#' @family EnergyPlus
#' @export
eplus_output <- function(run, name, key = NULL,
                         by = c("day", "hour", "month", "timestep", "run period")) {
  frequency <- reporting_frequencies()[[match_choice(by)]]
  check_eplus_run(run)
  con <- DBI::dbConnect(RSQLite::SQLite(), run$sql, flags = RSQLite::SQLITE_RO)
  on.exit(DBI::dbDisconnect(con), add = TRUE)
  entry <- output_entry(con, name, key, frequency)
  values <- DBI::dbGetQuery(con, paste(
    "SELECT t.Month AS month, t.Day AS day, t.Hour AS hour, t.Minute AS minute, d.Value AS value",
    "FROM ReportData d JOIN Time t ON d.TimeIndex = t.TimeIndex",
    "JOIN EnvironmentPeriods e ON t.EnvironmentPeriodIndex = e.EnvironmentPeriodIndex",
    "WHERE d.ReportDataDictionaryIndex = ? AND e.EnvironmentType = 3",
    "AND (t.WarmupFlag IS NULL OR t.WarmupFlag = 0) ORDER BY t.TimeIndex"),
    params = list(entry$ReportDataDictionaryIndex))
  units <- entry$Units
  if (units == "J") {
    values$value <- values$value / 3.6e6
    units <- "kWh"
  }
  structure(values, type = entry$Type, units = units)
}

# EnergyPlus's names of the reporting frequencies, by the package's `by`.
reporting_frequencies <- function() {
  c(day = "Daily", hour = "Hourly", month = "Monthly", timestep = "Timestep",
    `run period` = "RunPeriod")
}

# The dictionary row of `name` (and `key`) at `frequency`, or an error that
# lists what the run reported.
output_entry <- function(con, name, key, frequency, call = rlang::caller_env()) {
  dict <- DBI::dbGetQuery(con, "SELECT * FROM ReportDataDictionary")
  rows <- dict[tolower(dict$Name) == tolower(name) &
                 tolower(dict$ReportingFrequency) == tolower(frequency), ]
  if (!is.null(key)) rows <- rows[!is.na(rows$KeyValue) & tolower(rows$KeyValue) == tolower(key), ]
  if (nrow(rows) == 0L) {
    reported <- unique(sprintf("%s (%s)", dict$Name, dict$ReportingFrequency))
    abort_bayesbem(c("The run reported no {frequency} {.val {name}}{if (!is.null(key)) paste0(' for ', key)}.",
                     i = "It reported: {.val {utils::head(reported, 12)}}."),
                   "eplus_output", call = call)
  }
  if (nrow(rows) > 1L) {
    abort_bayesbem(c("{.val {name}} is reported for several objects: {.val {rows$KeyValue}}.",
                     i = "Choose one with {.arg key}."),
                   "eplus_output", call = call)
  }
  rows
}

# Meters are named "Resource:Place" (Electricity:Facility); output variables
# have no colon (Zone Mean Air Temperature).
is_meter <- function(name) grepl(":", name, fixed = TRUE)

# The model with `name` reported at `frequency` ("Daily", "Hourly"), as an
# Output:Meter or an Output:Variable (for every key: the key is chosen
# when reading).
with_output <- function(model, name, frequency = "Daily") {
  class <- if (is_meter(name)) "Output:Meter" else "Output:Variable"
  field <- if (is_meter(name)) "key_name" else "variable_name"
  present <- vapply(model$json[[class]] %||% list(), function(o) {
    tolower(o[[field]] %||% "") == tolower(name) &&
      tolower(o$reporting_frequency %||% "hourly") == tolower(frequency) &&
      (is_meter(name) || (o$key_value %||% "*") == "*")
  }, logical(1))
  if (any(present)) {
    return(model)
  }
  if (is_meter(name)) {
    eplus_add(model, class, key_name = name, reporting_frequency = frequency)
  } else {
    eplus_add(model, class, key_value = "*", variable_name = name, reporting_frequency = frequency)
  }
}

# Hourly values as the weather's records: EnergyPlus stamps an hour by its
# end (Hour 1 is 0:00 to 1:00), as EPW records are numbered, so the run
# must report the records' (month, day, hour) in order.
hourly_values <- function(values, hourly, call = rlang::caller_env()) {
  same <- nrow(values) == nrow(hourly) && all(values$month == hourly$month &
                                                values$day == hourly$day & values$hour == hourly$hour)
  if (!same) {
    abort_bayesbem(c("EnergyPlus reported {nrow(values)} hour{?s}, but the weather has {nrow(hourly)}.",
                     i = "Make the model's {.field RunPeriod} cover the weather file's days, from {hourly$month[1]}/{hourly$day[1]} to {hourly$month[nrow(hourly)]}/{hourly$day[nrow(hourly)]}."),
                   "eplus_output", call = call)
  }
  values$value
}

# Daily values summed (energy) or averaged (rates, temperatures) over the
# field periods: `days` are the weather's days (month, day) in order, which
# the run period must report, and `members` the days of each period.
aggregate_daily <- function(daily, days, members, call = rlang::caller_env()) {
  same <- nrow(daily) == nrow(days) && all(daily$month == days$month & daily$day == days$day)
  if (!same) {
    abort_bayesbem(c("EnergyPlus reported {nrow(daily)} day{?s}, but the weather has {nrow(days)}.",
                     i = "Make the model's {.field RunPeriod} cover the weather file's days, from {days$month[1]}/{days$day[1]} to {days$month[nrow(days)]}/{days$day[nrow(days)]}."),
                   "eplus_output", call = call)
  }
  combine <- if (identical(attr(daily, "type"), "Sum")) sum else mean
  # days in no period (between bills) count in none
  vapply(members, function(at) combine(daily$value[at]), numeric(1))
}
