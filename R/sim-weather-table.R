#' Weather as a station gives it, and as an EPW file
#'
#' `read_weather()` takes a weather station's hourly or sub-hourly table (a
#' data frame, or the path of a CSV file) with a time column in any time
#' zone and returns the hourly weather of the site in its standard time,
#' as the EPW format holds it, ready for [write_epw()]: the EPW file then
#' drives [bem_simulator()] and [eplus_simulator()] alike.
#'
#' * **Time.** Each reading's time is an instant (`POSIXct` in any zone, or
#'   text parsed in `tz`); `stamps` says whether it ends or starts the
#'   interval it stands for (stations and EPW files stamp an hour by its
#'   end). Readings are averaged into the hours of the site's standard time
#'   (`time_zone` hours from UTC, without summer time).
#' * **Humidity.** Relative humidity (`rh`, %) or the dew point
#'   (`dew_point`, C; converted with the Magnus formula of Alduchov and
#'   Eskridge 1996).
#' * **Radiation.** Global horizontal irradiance (`ghi`, W/m2). Direct
#'   normal and diffuse horizontal irradiance (`dni`, `dhi`), when the
#'   station gives none, are split from it by the decomposition of Erbs,
#'   Klein and Duffie (1982), at the sun's position in the middle of each
#'   hour (Spencer 1971's declination and equation of time).
#' * **Gaps and fills.** An hour without a reading (or with `NA`) is
#'   interpolated linearly when the gap is at most `max_gap` hours; a
#'   longer gap is an error (class `bayesbem_error_weather`) naming its
#'   first hours. Hours the station itself marked as filled (`flagged`, a
#'   logical column) are kept and counted. One message says how many hours
#'   were interpolated and flagged.
#'
#' @param x A data frame, or the path of a CSV file, one row per reading.
#' @param latitude,longitude The site's position (degrees, north and east
#'   positive).
#' @param elevation The site's elevation (m), for the air pressure.
#' @param time_zone The site's standard time, hours from UTC (e.g. 0 for
#'   the United Kingdom, -7 for Colorado).
#' @param columns The names of the columns in `x`: `time`, `temp` (dry
#'   bulb, C), `rh` or `dew_point`, `ghi`, and optionally `dni`, `dhi`,
#'   `wind_speed` (m/s), `wind_direction` (degrees) and `flagged`. Only the
#'   names that differ need be given, e.g. `c(time = "ob_time", temp =
#'   "air_temperature")`.
#' @param tz The time zone in which text times are read (e.g. `"UTC"`).
#' @param stamps Whether a reading's time is the `"end"` or the `"start"` of
#'   its interval.
#' @param days Optional: the first and last day to keep (`Date`s, in the
#'   site's standard time), e.g. a calendar year of a station whose file
#'   of that year starts with the last hour of the year before (stamped at
#'   its end, midnight). An hour of those days without a reading is a gap.
#' @param max_gap The longest run of missing hours filled by interpolation.
#' @param name The site's name, for the EPW header.
#' @return An object of class `bayesbem_weather`: a data frame of hours
#'   (`time`, the hour's start in standard time; `temp`, `rh`, `dew_point`,
#'   `pressure`, `ghi`, `dni`, `dhi`, `wind_speed`, `wind_direction`,
#'   `filled`: how the hour was obtained, `"measured"`, `"flagged"` or
#'   `"interpolated"`), with the site as attributes.
#' @references Erbs, D. G., Klein, S. A. and Duffie, J. A. (1982).
#'   Estimation of the diffuse radiation fraction for hourly, daily and
#'   monthly-average global radiation. *Solar Energy* 28(4), 293-302.
#'
#'   Spencer, J. W. (1971). Fourier series representation of the position
#'   of the sun. *Search* 2(5), 172.
#'
#'   Alduchov, O. A. and Eskridge, R. E. (1996). Improved Magnus form
#'   approximation of saturation vapor pressure. *Journal of Applied
#'   Meteorology* 35(4), 601-609.
#' @family simulation
#' @export
#' @examples
#' # a station's table: UTC stamps at each hour's end, global radiation only
#' epw <- epw_weather(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"),
#'                    by = "hour")
#' station <- data.frame(ob_time = epw$time + 3600, temp = epw$temp, rh = epw$rh,
#'                       ghi = epw$ghi)
#' weather <- read_weather(station, latitude = 39.74, longitude = -105.18,
#'                         elevation = 1829, time_zone = -7,
#'                         columns = c(time = "ob_time"))
#' weather
#' path <- write_epw(weather, tempfile(fileext = ".epw"))
#' head(epw_monthly(path))
read_weather <- function(x, latitude, longitude, elevation, time_zone,
                         columns = NULL, tz = "UTC", stamps = c("end", "start"),
                         days = NULL, max_gap = 3L, name = "site") {
  stamps <- match_choice(stamps)
  check_between(latitude, -90, 90)
  check_between(longitude, -180, 180)
  check_between(elevation, -500, 9000)
  check_between(time_zone, -12, 14)
  check_count(max_gap + 1L, arg = "max_gap + 1")
  readings <- weather_readings(x, columns, tz, stamps)
  hours <- hourly_means(readings, time_zone, check_days(days))
  hours <- fill_gaps(hours, max_gap)
  if (is.null(hours$rh)) hours$rh <- relative_humidity(hours$temp, hours$dew_point)
  if (is.null(hours$dew_point)) hours$dew_point <- dew_point(hours$temp, hours$rh)
  if (is.null(hours$dni) || is.null(hours$dhi)) {
    split <- erbs_split(hours$ghi, hours$time, latitude, longitude, time_zone)
    hours$dni <- split$dni
    hours$dhi <- split$dhi
  }
  hours$pressure <- 101325 * (1 - 2.25577e-5 * elevation)^5.25588
  for (col in c("wind_speed", "wind_direction")) if (is.null(hours[[col]])) hours[[col]] <- NA_real_
  inform_filled(hours$filled)
  structure(hours[c("time", "temp", "rh", "dew_point", "pressure", "ghi", "dni", "dhi",
                    "wind_speed", "wind_direction", "filled")],
            class = c("bayesbem_weather", "data.frame"),
            site = list(name = name, latitude = latitude, longitude = longitude,
                        elevation = elevation, time_zone = time_zone))
}

#' @export
print.bayesbem_weather <- function(x, ...) {
  rlang::check_dots_empty()
  site <- attr(x, "site")
  filled <- table(factor(x$filled, levels = c("measured", "flagged", "interpolated")))
  cat_lines("Hourly weather of {site$name} ({site$latitude}, {site$longitude}, {site$elevation} m), standard time UTC{sprintf('%+g', site$time_zone)}",
            "  {format(x$time[1])} to {format(x$time[nrow(x)])}: {nrow(x)} hours ({filled[['measured']]} measured, {filled[['flagged']]} flagged, {filled[['interpolated']]} interpolated)")
  print(utils::head(as.data.frame(x)[c("time", "temp", "rh", "ghi", "dni", "dhi")]), row.names = FALSE)
  invisible(x)
}

# The readings as a table of `time` (POSIXct), the measured columns by
# their package names, and `start`: each reading's interval start (s).
weather_readings <- function(x, columns, tz, stamps, call = rlang::caller_env()) {
  if (is.character(x) && length(x) == 1L) {
    if (!file.exists(x)) {
      abort_bayesbem("{.file {x}} does not exist.", "weather", call = call)
    }
    x <- utils::read.csv(x, check.names = FALSE, stringsAsFactors = FALSE)
  }
  if (!is.data.frame(x)) {
    abort_bayesbem("{.arg x} must be a data frame or the path of a CSV file, not {.obj_type_friendly {x}}.",
                   "argument", call = call)
  }
  known <- c("time", "temp", "rh", "dew_point", "ghi", "dni", "dhi", "wind_speed",
             "wind_direction", "flagged")
  if (!is.null(columns) && (!is.character(columns) || is.null(names(columns)) ||
                            !all(names(columns) %in% known))) {
    abort_bayesbem(c("{.arg columns} must name columns of {.arg x} by what they hold.",
                     i = "Its names are among {.val {known}}, e.g. {.code c(time = \"ob_time\")}."),
                   "argument", call = call)
  }
  names_of <- stats::setNames(known, known)
  names_of[names(columns)] <- columns
  needed <- c("time", "temp", "ghi")
  humidity <- intersect(c("rh", "dew_point"), names(names_of)[names_of %in% names(x)])
  absent <- needed[!names_of[needed] %in% names(x)]
  if (length(absent) > 0L || length(humidity) == 0L) {
    abort_bayesbem(c("{.arg x} lacks the columns of {.field {c(absent, if (length(humidity) == 0L) 'rh or dew_point')}}.",
                     x = "Its columns are {.field {names(x)}}.",
                     i = "Name them in {.arg columns}, e.g. {.code columns = c(temp = \"air_temperature\")}."),
                   "columns", call = call)
  }
  present <- names(names_of)[names_of %in% names(x)]
  out <- stats::setNames(x[names_of[present]], present)
  out$time <- weather_times(out$time, tz, call)
  for (col in setdiff(present, c("time", "flagged"))) {
    if (!is.numeric(out[[col]])) {
      abort_bayesbem("Column {.field {names_of[[col]]}} ({col}) of {.arg x} must be numeric, not {.obj_type_friendly {out[[col]]}}.",
                     "columns", call = call)
    }
  }
  if (!is.null(out$flagged)) out$flagged <- as.logical(out$flagged) %in% TRUE
  step <- stats::median(diff(sort(as.numeric(out$time))))
  out$start <- as.numeric(out$time) - if (stamps == "end") step else 0
  out
}

# Text times read element by element in the first of the ISO 8601 forms
# that reads each.
weather_times <- function(time, tz, call) {
  parsed <- time
  if (!inherits(time, "POSIXct")) {
    parsed <- as.POSIXct(rep(NA_real_, length(time)), origin = "1970-01-01", tz = tz)
    for (form in c("%Y-%m-%d %H:%M:%OS", "%Y-%m-%dT%H:%M:%OS", "%Y-%m-%d %H:%M", "%Y-%m-%dT%H:%M")) {
      todo <- is.na(parsed)
      parsed[todo] <- as.POSIXct(as.character(time[todo]), format = form, tz = tz)
    }
  }
  bad <- which(is.na(parsed))
  if (length(bad) > 0L) {
    abort_bayesbem(c("{length(bad)} reading{?s} without a readable time.",
                     x = "{cli::qty(length(bad))}Row{?s} {utils::head(bad, 5)}{if (!inherits(time, 'POSIXct')) paste0(': \"', utils::head(time[bad], 2), '\"', collapse = ',') else ''}.",
                     i = "Give {.cls POSIXct} times, or text such as {.val 2013-01-01 13:00} in {.arg tz}."),
                   "weather", call = call)
  }
  parsed
}

check_days <- function(days, call = rlang::caller_env()) {
  if (is.null(days)) {
    return(NULL)
  }
  if (!inherits(days, "Date") || length(days) != 2L || anyNA(days) || days[2] < days[1]) {
    abort_bayesbem("{.arg days} must be two {.cls Date}s, the first and the last day to keep, not {describe_value(days)}.",
                   "argument", call = call)
  }
  days
}

# The readings averaged into the hours of standard time (UTC + `time_zone`
# hours), from the first hour to the last, an hour without any reading all
# NA; `filled` is "flagged" for an hour any of whose readings the station
# flagged.
hourly_means <- function(readings, time_zone, days = NULL, call = rlang::caller_env()) {
  offset <- time_zone * 3600
  hour <- floor((readings$start + offset) / 3600)
  if (!is.null(days)) {
    # the hours of those days, counted from 1970-01-01 in standard time
    all_hours <- seq(as.numeric(days[1]) * 24, as.numeric(days[2]) * 24 + 23)
    kept <- hour %in% all_hours
    if (!any(kept)) {
      abort_bayesbem("No reading falls on {.arg days}, {format(days[1])} to {format(days[2])}.",
                     "weather", call = call)
    }
    readings <- readings[kept, , drop = FALSE]
    hour <- hour[kept]
  } else {
    all_hours <- seq(min(hour), max(hour))
  }
  at <- factor(hour, levels = all_hours)
  zone <- if (time_zone == 0) "UTC" else if (time_zone == round(time_zone)) sprintf("Etc/GMT%+d", -time_zone) else "UTC"
  out <- data.frame(time = as.POSIXct(all_hours * 3600 - offset, origin = "1970-01-01", tz = zone))
  for (col in setdiff(names(readings), c("time", "start", "flagged"))) {
    out[[col]] <- as.vector(tapply(readings[[col]], at, mean, na.rm = TRUE))
    out[[col]][is.nan(out[[col]])] <- NA_real_
  }
  flagged <- if (is.null(readings$flagged)) rep(FALSE, length(all_hours)) else
    as.vector(tapply(readings$flagged, at, any)) %in% TRUE
  out$filled <- ifelse(flagged, "flagged", "measured")
  out
}

# Runs of at most `max_gap` missing hours of each quantity interpolated
# linearly between their neighbours; a longer run, or one at either end,
# is an error naming its first hours.
fill_gaps <- function(hours, max_gap, call = rlang::caller_env()) {
  for (col in setdiff(names(hours), c("time", "filled", "wind_direction"))) {
    v <- hours[[col]]
    missing <- is.na(v)
    if (!any(missing)) next
    runs <- rle(missing)
    ends <- cumsum(runs$lengths)
    starts <- ends - runs$lengths + 1L
    long <- runs$values & (runs$lengths > max_gap | starts == 1L | ends == length(v))
    if (any(long)) {
      first <- which(long)[1]
      abort_bayesbem(c("{.field {col}} is missing for {runs$lengths[first]} hour{?s} in a row from {format(hours$time[starts[first]], '%Y-%m-%d %H:%M %Z')}.",
                       x = "Gaps of up to {max_gap} hour{?s} between readings are interpolated; {sum(runs$lengths[long])} hour{?s} in {sum(long)} longer or unbounded gap{?s} cannot be.",
                       i = "Fill them from another station, raise {.arg max_gap}, or keep the weather of the period the station covers."),
                     "weather", call = call)
    }
    hours[[col]] <- stats::approx(which(!missing), v[!missing], seq_along(v))$y
    hours$filled[missing] <- "interpolated"
  }
  hours
}

inform_filled <- function(filled) {
  counts <- table(factor(filled, levels = c("flagged", "interpolated")))
  if (sum(counts) == 0L) {
    return(invisible())
  }
  cli::cli_inform(c(i = "Of {length(filled)} hours of weather, {counts[['interpolated']]} {?was/were} interpolated over gaps and {counts[['flagged']]} {?was/were} flagged by the station as filled."),
                  class = "bayesbem_message_weather_filled")
}

# Magnus formula over water (Alduchov and Eskridge 1996): saturation vapour
# pressure es(T) = 6.1094 exp(17.625 T / (T + 243.04)) hPa; rh = 100 e / es.
magnus <- function(temp) 6.1094 * exp(17.625 * temp / (temp + 243.04))

relative_humidity <- function(temp, dew_point) pmin(100, 100 * magnus(dew_point) / magnus(temp))

dew_point <- function(temp, rh) {
  g <- log(pmax(rh, 1) / 100) + 17.625 * temp / (temp + 243.04)
  243.04 * g / (17.625 - g)
}

# The sun's position in the middle of each hour starting at `time`: the
# cosine of its zenith angle, and the extraterrestrial irradiance on a
# horizontal plane (W/m2). Spencer (1971): declination and equation of
# time from the day angle; the hour angle from the local solar time.
solar_geometry <- function(time, latitude, longitude, time_zone) {
  mid <- as.numeric(time) + 1800
  standard <- mid + time_zone * 3600
  day <- floor(standard / 86400)
  doy <- as.integer(format(as.Date(day, origin = "1970-01-01"), "%j"))
  clock <- (standard %% 86400) / 3600
  g <- 2 * pi * (doy - 1) / 365
  declination <- 0.006918 - 0.399912 * cos(g) + 0.070257 * sin(g) - 0.006758 * cos(2 * g) +
    0.000907 * sin(2 * g) - 0.002697 * cos(3 * g) + 0.00148 * sin(3 * g)
  eot <- 229.18 * (0.000075 + 0.001868 * cos(g) - 0.032077 * sin(g) - 0.014615 * cos(2 * g) -
                     0.040849 * sin(2 * g))
  solar_time <- clock + (4 * (longitude - 15 * time_zone) + eot) / 60
  hour_angle <- (solar_time - 12) * pi / 12
  phi <- latitude * pi / 180
  cos_zenith <- sin(phi) * sin(declination) + cos(phi) * cos(declination) * cos(hour_angle)
  # the eccentricity correction, Spencer (1971)
  distance <- 1.000110 + 0.034221 * cos(g) + 0.001280 * sin(g) + 0.000719 * cos(2 * g) +
    0.000077 * sin(2 * g)
  list(cos_zenith = cos_zenith, extraterrestrial = pmax(1367 * distance * cos_zenith, 0))
}

# Direct normal and diffuse horizontal irradiance from the global by the
# diffuse fraction of Erbs, Klein and Duffie (1982), eq. 1, of the
# clearness index kt = ghi / extraterrestrial horizontal irradiance:
#   1 - 0.09 kt                                                kt <= 0.22
#   0.9511 - 0.1604 kt + 4.388 kt^2 - 16.638 kt^3 + 12.336 kt^4  kt <= 0.80
#   0.165                                                      kt > 0.80
# With the sun below 5 degrees of elevation all the radiation is diffuse.
erbs_split <- function(ghi, time, latitude, longitude, time_zone) {
  ghi <- pmax(ghi, 0)
  sun <- solar_geometry(time, latitude, longitude, time_zone)
  low <- sun$cos_zenith < sin(5 * pi / 180)
  kt <- ifelse(low, 0, pmin(ghi / sun$extraterrestrial, 1))
  fraction <- ifelse(kt <= 0.22, 1 - 0.09 * kt,
                     ifelse(kt <= 0.8, 0.9511 - 0.1604 * kt + 4.388 * kt^2 - 16.638 * kt^3 +
                              12.336 * kt^4, 0.165))
  dhi <- ghi * fraction
  dni <- ifelse(low, 0, (ghi - dhi) / pmax(sun$cos_zenith, sin(5 * pi / 180)))
  list(dni = dni, dhi = dhi)
}

#' @rdname read_weather
#' @param weather A `bayesbem_weather` from `read_weather()`.
#' @param path Where to write the EPW file.
#' @return `write_epw()`: `path`, invisibly. The file holds the hours as EPW
#'   records (each numbered by the hour it ends, in standard time), with
#'   the site's header; quantities the station lacks get the EPW format's
#'   missing codes, which EnergyPlus replaces by its defaults.
#' @export
write_epw <- function(weather, path) {
  if (!inherits(weather, "bayesbem_weather")) {
    abort_bayesbem("{.arg weather} must be weather from {.fn read_weather}, not {.obj_type_friendly {weather}}.",
                   "argument")
  }
  if (!is.character(path) || length(path) != 1L || !dir.exists(dirname(path))) {
    abort_bayesbem("{.arg path} must be a file path in an existing folder, not {describe_value(path)}.",
                   "argument")
  }
  site <- attr(weather, "site")
  # the record of the hour ending at time + 1 h, in standard time: hour 24
  # of a day is that day's last hour
  end <- weather$time + 3600 - 1
  zone <- attr(weather$time, "tzone") %||% "UTC"
  date <- as.Date(format(end, "%Y-%m-%d", tz = zone))
  code <- function(v, missing) ifelse(is.na(v), missing, v)
  records <- data.frame(
    year = format(date, "%Y"), month = as.integer(format(date, "%m")),
    day = as.integer(format(date, "%d")), hour = as.integer(format(end, "%H", tz = zone)) + 1L,
    minute = 0L, flags = "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9*9*9*9",
    temp = sprintf("%.1f", weather$temp), dew_point = sprintf("%.1f", weather$dew_point),
    rh = round(weather$rh), pressure = round(weather$pressure),
    extraterrestrial = 9999, extraterrestrial_normal = 9999, infrared = 9999,
    ghi = round(pmax(weather$ghi, 0)), dni = round(pmax(weather$dni, 0)),
    dhi = round(pmax(weather$dhi, 0)),
    global_lux = 999999, direct_lux = 999999, diffuse_lux = 999999, zenith_lux = 9999,
    wind_direction = code(round(weather$wind_direction), 999),
    wind_speed = code(sprintf("%.1f", weather$wind_speed), 999),
    total_sky = 99, opaque_sky = 99, visibility = 9999, ceiling = 99999, observation = 9,
    weather_codes = 999999999, water = 999, aerosol = 0.999, snow = 999, days_snow = 99,
    albedo = 999, rain = 999, rain_rate = 99
  )
  records$wind_speed[is.na(weather$wind_speed)] <- "999"
  first <- weekday_names[as.integer(format(date[1], "%u"))]
  header <- c(
    sprintf("LOCATION,%s,-,-,bayesbem read_weather(),-,%.4f,%.4f,%.1f,%.1f", site$name,
            site$latitude, site$longitude, site$time_zone, site$elevation),
    "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
    "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
    "COMMENTS 1,Written by bayesbem::write_epw() from a weather station's hourly table",
    "COMMENTS 2,Direct normal and diffuse radiation split from the global (Erbs et al. 1982) where the station gives none",
    sprintf("DATA PERIODS,1,1,Data,%s,%s,%s", first, format_epw_day(date[1]),
            format_epw_day(date[length(date)]))
  )
  writeLines(c(header, do.call(paste, c(unname(records), sep = ","))), path)
  invisible(path)
}

format_epw_day <- function(date) sprintf("%d/%d", as.integer(format(date, "%m")),
                                         as.integer(format(date, "%d")))
