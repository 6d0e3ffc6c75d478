#' Weather by month, week, day, hour or the data's own periods from an EPW file
#'
#' Reads the hourly records of an EPW file (plain or gzip-compressed) and
#' returns, for each period, the means of the quantities that drive a
#' building model, plus heating and cooling degree-days. `epw_weather()`
#' summarises by `"month"`, `"week"` (seven consecutive days from the first
#' record) or `"day"`; `epw_monthly()` and `epw_daily()` are its monthly and
#' daily forms. Periods follow the records in the order they appear, so any
#' year works: a leap year's 29 February counts in February, and
#' typical-year files (whose months come from different years) are handled.
#'
#' Bills do not run on calendar months: with `periods` (each bill's first
#' and last day, inclusive), the rows are those periods, in their order.
#' They may differ in length and leave gaps (a missing bill); overlapping,
#' unsorted or backwards periods and periods with days the file lacks are
#' errors of class `bayesbem_error_periods` naming the rows. A file of
#' actual weather is matched by date; a typical-year file by month and day
#' (it has no 29 February: a period holding one holds a day less).
#' Values equal to the EPW format's missing-value codes (99.9 for
#' temperatures, 999 for relative humidity, 9999 for radiation) are left out
#' of the means; a period with no valid value of a quantity is an error.
#'
#' The monthly means of dry-bulb temperature and relative humidity of the
#' shipped 2013 weather file are exactly the observable inputs `temp` and
#' `rh` of [seb_field]. Daily tables drive [bem_simulator()] as monthly ones
#' do (each row is a period of `hours` hours).
#'
#' @param epw_path Path to an `.epw` or `.epw.gz` file.
#' @param by `"month"`, `"week"`, `"day"` or `"hour"`.
#' @param periods Instead of `by`, the measurements' own periods: a data
#'   frame with columns `start` and `end` (each period's first and last
#'   day: `Date`s or `"YYYY-MM-DD"` strings), e.g. a table of bills.
#' @param base_heating,base_cooling Base temperatures (degrees C) of the
#'   heating and cooling degree-days, computed from daily mean temperatures.
#' @return A data frame with one row per period: `date` and `end` (its
#'   first and last day, `Date`s: the year is the records' own, or the
#'   data's with `periods`), `month` (1-12, of the first day), `days`,
#'   `hours` (those the file holds), `temp` (mean dry-bulb temperature, degrees C),
#'   `rh` (mean relative humidity, percent), `solar` (mean direct normal
#'   radiation, W/m2: the observable inputs `temp`, `rh` and `solar` of the
#'   simulators and of [seb_field], so the table can be given to
#'   [predict()] as it is), `dni` (the same, under the EPW's name), `dhi` (mean diffuse horizontal radiation, W/m2),
#'   `ghi` (mean global horizontal radiation, W/m2), `hdd` and `cdd`
#'   (degree-days, K day). By hour, one row per record, with also `time`
#'   (the hour's start, `POSIXct` in the file's standard time: EPW records
#'   are numbered by the hour they end and ignore daylight-saving time),
#'   `hour` (0-23, of `time`) and `weekday` (1 Monday to 7 Sunday: by the
#'   calendar for actual weather, from the header's first day for a
#'   typical year); `hdd` and `cdd` are then the hour's share of degree-days
#'   from its own temperature, and a missing value is an error.
#' @family simulation
#' @export
#' @examples
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' w <- epw_monthly(epw)
#' w
#' all.equal(w$temp, seb_field$temp)
#' head(epw_daily(epw))
#' head(epw_weather(epw, by = "week"))
#' # bills read on their own days
#' bills <- data.frame(start = as.Date(c("2013-01-05", "2013-02-04", "2013-03-06")),
#'                     end = as.Date(c("2013-02-03", "2013-03-05", "2013-04-03")))
#' epw_weather(epw, periods = bills)
epw_weather <- function(epw_path, by = c("month", "week", "day", "hour"), periods = NULL,
                        base_heating = 18.3, base_cooling = 18.3) {
  check_by_or_periods(by, periods)
  by <- match_choice(by)
  if (!is.null(periods)) periods <- check_periods(periods)
  check_number(base_heating, "argument")
  check_number(base_cooling, "argument")
  hourly <- read_epw_hourly(epw_path)
  if (by == "hour") {
    return(hourly_weather(hourly, epw_path, base_heating, base_cooling))
  }
  summarise_epw(hourly, by, base_heating, base_cooling, epw_path, periods = periods)
}

# A resolution or the data's own periods, not both.
check_by_or_periods <- function(by, periods, call = rlang::caller_env()) {
  if (!is.null(periods) && length(by) == 1L) {
    abort_bayesbem(c("Give either {.arg by} or {.arg periods}, not both.",
                     i = "{.arg periods} are the measurements' own days; {.arg by} cuts the weather into calendar periods."),
                   "argument", call = call)
  }
}

# epw_weather() on records already read (`path` for messages): one row per
# period of `by`, or per row of `periods` (checked) when given.
summarise_epw <- function(hourly, by, base_heating = 18.3, base_cooling = 18.3, path,
                          periods = NULL, call = rlang::caller_env()) {
  day <- record_days(hourly)
  period <- if (is.null(periods)) {
    record_periods(hourly, day, by)
  } else {
    period_of_days(weather_days(hourly, "day"), periods, path, call)[day]
  }
  kept <- !is.na(period)
  hourly <- hourly[kept, , drop = FALSE]
  day <- day[kept]
  period <- period[kept]
  daily_temp <- tapply(hourly$temp, day, mean, na.rm = TRUE)
  day_period <- tapply(period, day, `[`, 1)
  # each period's first and last record (of a typical year, a period over
  # the year's end holds January before December: its dates are the data's)
  ids <- sort(unique(period))
  first <- match(ids, period)
  last <- length(period) + 1L - match(ids, rev(period))
  date_of <- function(at) record_dates(hourly[at, , drop = FALSE])
  mean_by <- function(v) as.vector(tapply(v, period, mean, na.rm = TRUE))
  out <- data.frame(
    date = if (is.null(periods)) date_of(first) else periods$start,
    end = if (is.null(periods)) date_of(last) else periods$end,
    month = if (is.null(periods)) hourly$month[first] else as.integer(format(periods$start, "%m")),
    days = as.vector(table(day_period)),
    hours = as.vector(table(period)),
    temp = mean_by(hourly$temp),
    rh = mean_by(hourly$rh),
    solar = mean_by(hourly$dni),
    dni = mean_by(hourly$dni),
    dhi = mean_by(hourly$dhi),
    ghi = mean_by(hourly$ghi),
    hdd = as.vector(tapply(pmax(base_heating - daily_temp, 0), day_period, sum)),
    cdd = as.vector(tapply(pmax(daily_temp - base_cooling, 0), day_period, sum)),
    row.names = NULL
  )
  empty <- vapply(out[c("temp", "rh", "dni", "dhi", "ghi")], function(v) any(!is.finite(v)),
                  logical(1))
  if (any(empty)) {
    abort_bayesbem(c("{.file {path}} has a {by} without any valid {.field {names(empty)[empty]}} value.",
                     i = "Fill the missing records (EPW missing codes) before using the file."),
                   "weather", call = call)
  }
  out
}

#' @rdname epw_weather
#' @export
epw_monthly <- function(epw_path, base_heating = 18.3, base_cooling = 18.3) {
  epw_weather(epw_path, "month", base_heating = base_heating, base_cooling = base_cooling)
}

#' @rdname epw_weather
#' @export
epw_daily <- function(epw_path, base_heating = 18.3, base_cooling = 18.3) {
  epw_weather(epw_path, "day", base_heating = base_heating, base_cooling = base_cooling)
}

# Days and months in the order of the records: a new one where the field
# changes; weeks are seven days from the first record.
record_days <- function(hourly) new_run(hourly$month * 100 + hourly$day)

record_periods <- function(hourly, day, by) {
  switch(by, month = new_run(hourly$month), week = (day - 1L) %/% 7L + 1L, day = day)
}

new_run <- function(v) cumsum(c(TRUE, v[-1] != v[-length(v)]))

# Each day of an EPW file (year, month, day) with its period of `by`, in
# order.
weather_days <- function(hourly, by) {
  day <- record_days(hourly)
  first <- !duplicated(day)
  data.frame(year = hourly$year[first], month = hourly$month[first], day = hourly$day[first],
             period = record_periods(hourly, day, by)[first])
}

# The days (rows of weather_days()) each period sums: those of `by`, or of
# each of the union of the measurements' periods (check_output_periods()).
period_members <- function(days, periods, path, call = rlang::caller_env()) {
  if (is.null(periods)) {
    return(unname(split(seq_len(nrow(days)), days$period)))
  }
  union <- union_periods(periods)
  lapply(seq_len(nrow(union)), function(i) {
    which(!is.na(period_of_days(days, union[i, , drop = FALSE], path, call)))
  })
}

# The weather over each of the union's periods (epw_weather(periods = )
# of each table, which may overlap one another).
periods_weather <- function(hourly, tables, path, call = rlang::caller_env()) {
  rows <- do.call(rbind, lapply(unname(tables), function(t) {
    summarise_epw(hourly, "month", path = path, periods = t, call = call)
  }))
  union <- union_periods(tables)
  out <- rows[match(paste(union$start, union$end), paste(rows$date, rows$end)), , drop = FALSE]
  rownames(out) <- NULL
  out
}


# The hourly records of an EPW file with missing-value codes set to NA.
read_epw_hourly <- function(epw_path, call = rlang::caller_env()) {
  if (!is.character(epw_path) || length(epw_path) != 1L || !file.exists(epw_path)) {
    abort_bayesbem(c("{.arg epw_path} must be the path of an existing EPW file.",
                     x = "{.file {epw_path}} does not exist."),
                   "weather", call = call)
  }
  header <- readLines(epw_path, n = 8L, warn = FALSE)
  if (length(header) < 8L || !startsWith(header[1], "LOCATION") ||
      !startsWith(header[8], "DATA PERIODS")) {
    abort_bayesbem(c("{.file {epw_path}} is not an EPW weather file.",
                     i = "An EPW file starts with 8 header lines, from LOCATION to DATA PERIODS."),
                   "weather", call = call)
  }
  raw <- utils::read.csv(epw_path, skip = 8L, header = FALSE, colClasses = "character",
                         strip.white = TRUE)
  if (ncol(raw) < 16L || nrow(raw) < 1L) {
    abort_bayesbem("{.file {epw_path}} has no hourly records with at least 16 fields.",
                   "weather", call = call)
  }
  field <- function(i, missing_code) {
    v <- suppressWarnings(as.numeric(raw[[i]]))
    v[!is.na(v) & v >= missing_code] <- NA_real_
    v
  }
  # EPW fields: 1 year, 2 month, 3 day, 4 hour (1-24, the hour ending), 7
  # dry bulb, 9 relative humidity, 14 global horizontal, 15 direct normal,
  # 16 diffuse horizontal radiation; the header's LOCATION ends with the
  # time zone (hours from GMT), DATA PERIODS gives the first day's weekday
  location <- strsplit(header[1], ",")[[1]]
  periods <- trimws(strsplit(header[8], ",")[[1]])
  structure(
    data.frame(year = as.integer(raw[[1]]), month = as.integer(raw[[2]]),
               day = as.integer(raw[[3]]), hour = as.integer(raw[[4]]),
               temp = field(7, 99.9), rh = field(9, 999),
               ghi = field(14, 9999), dni = field(15, 9999), dhi = field(16, 9999)),
    time_zone = suppressWarnings(as.numeric(location[9])),
    first_weekday = match(tolower(periods[5]), tolower(weekday_names))
  )
}

weekday_names <- c("Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday", "Sunday")

# Each record's day of the week, 1 (Monday) to 7: a file of actual weather
# (consecutive dates) by the calendar, a typical year from the weekday its
# DATA PERIODS line gives the first day, as EnergyPlus counts them.
record_weekdays <- function(hourly, day = record_days(hourly)) {
  dates <- record_dates(hourly)
  if (actual_weather(dates)) {
    return(as.integer(format(dates, "%u")))
  }
  start <- attr(hourly, "first_weekday")
  if (is.null(start) || is.na(start)) start <- 1L
  as.integer((start - 1L + day - 1L) %% 7L + 1L)
}

# epw_weather(by = "hour"): every record, its hour starting at `time` in
# the file's standard time (EPW records end the hour they are numbered).
hourly_weather <- function(hourly, path, base_heating = 18.3, base_cooling = 18.3,
                           call = rlang::caller_env()) {
  missing <- vapply(hourly[c("temp", "rh", "dni", "dhi", "ghi")], function(v) sum(is.na(v)), integer(1))
  if (any(missing > 0L)) {
    first <- which(is.na(hourly[[names(missing)[missing > 0L][1]]]))[1]
    abort_bayesbem(c("{.file {path}} has missing values (EPW missing codes) that an hourly model cannot run on.",
                     x = "{.field {names(missing)[missing > 0L]}}: {missing[missing > 0L]} hour{?s}; the first on {hourly$year[first]}-{hourly$month[first]}-{hourly$day[first]}, hour {hourly$hour[first]}.",
                     i = "Fill them (e.g. by interpolation) before an hourly simulation."),
                   "weather", call = call)
  }
  offset <- attr(hourly, "time_zone")
  zone <- if (!is.na(offset) && offset == round(offset)) {
    if (offset == 0) "UTC" else sprintf("Etc/GMT%+d", -offset)
  } else {
    "UTC"
  }
  dates <- record_dates(hourly)
  start <- as.POSIXct(paste(format(dates), sprintf("%02d:00:00", hourly$hour - 1L)), tz = zone)
  data.frame(time = start, date = dates, end = dates, month = hourly$month,
             hour = hourly$hour - 1L, weekday = record_weekdays(hourly),
             days = 1 / 24, hours = 1, temp = hourly$temp, rh = hourly$rh, solar = hourly$dni,
             dni = hourly$dni, dhi = hourly$dhi, ghi = hourly$ghi,
             hdd = pmax(base_heating - hourly$temp, 0) / 24,
             cdd = pmax(hourly$temp - base_cooling, 0) / 24)
}
