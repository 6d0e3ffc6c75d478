#' Monthly weather from an EnergyPlus weather (EPW) file
#'
#' Reads the hourly records of an EPW file (plain or gzip-compressed) and
#' returns monthly means of the quantities that drive a monthly building
#' model, plus heating and cooling degree-days. Months are taken from the
#' records' month field, in the order they appear, so any year works: a leap
#' year's 29 February counts in February, and typical-year files (whose
#' months come from different years) are handled. Values equal to the EPW
#' format's missing-value codes (99.9 for temperatures, 999 for relative
#' humidity, 9999 for radiation) are left out of the means; a month with no
#' valid value of a quantity is an error.
#'
#' The monthly means of dry-bulb temperature and relative humidity of the
#' shipped 2013 weather file are exactly the observable inputs `temp` and
#' `rh` of [seb_field].
#'
#' @param epw_path Path to an `.epw` or `.epw.gz` file.
#' @param base_heating,base_cooling Base temperatures (degrees C) of the
#'   heating and cooling degree-days, computed from daily mean temperatures.
#' @return A data frame with one row per month: `month` (1-12), `days`,
#'   `hours`, `temp` (mean dry-bulb temperature, degrees C), `rh` (mean
#'   relative humidity, percent), `dni` (mean direct normal radiation, W/m2),
#'   `dhi` (mean diffuse horizontal radiation, W/m2), `ghi` (mean global
#'   horizontal radiation, W/m2), `hdd` and `cdd` (degree-days, K day).
#' @family simulation
#' @export
#' @examples
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' w <- epw_monthly(epw)
#' w
#' all.equal(w$temp, seb_field$temp)
epw_monthly <- function(epw_path, base_heating = 18.3, base_cooling = 18.3) {
  hourly <- read_epw_hourly(epw_path)
  month <- factor(hourly$month, levels = unique(hourly$month))
  mean_by_month <- function(v) vapply(split(v, month), mean, numeric(1), na.rm = TRUE)
  day_key <- paste(hourly$month, hourly$day)
  daily <- data.frame(month = tapply(hourly$month, day_key, `[`, 1),
                      temp = tapply(hourly$temp, day_key, mean, na.rm = TRUE))
  daily_month <- factor(daily$month, levels = levels(month))
  out <- data.frame(
    month = as.integer(levels(month)),
    days = as.vector(table(daily_month)),
    hours = as.vector(table(month)),
    temp = mean_by_month(hourly$temp),
    rh = mean_by_month(hourly$rh),
    dni = mean_by_month(hourly$dni),
    dhi = mean_by_month(hourly$dhi),
    ghi = mean_by_month(hourly$ghi),
    hdd = as.vector(tapply(pmax(base_heating - daily$temp, 0), daily_month, sum)),
    cdd = as.vector(tapply(pmax(daily$temp - base_cooling, 0), daily_month, sum)),
    row.names = NULL
  )
  empty <- vapply(out[c("temp", "rh", "dni", "dhi", "ghi")], function(v) any(!is.finite(v)),
                  logical(1))
  if (any(empty)) {
    abort_bayesbem(c("{.file {epw_path}} has a month without any valid {.field {names(empty)[empty]}} value.",
                     i = "Fill the missing records (EPW missing codes) before using the file."),
                   "weather")
  }
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
  # EPW fields: 2 month, 3 day, 7 dry bulb, 9 relative humidity,
  # 14 global horizontal, 15 direct normal, 16 diffuse horizontal radiation
  data.frame(month = as.integer(raw[[2]]), day = as.integer(raw[[3]]),
             temp = field(7, 99.9), rh = field(9, 999),
             ghi = field(14, 9999), dni = field(15, 9999), dhi = field(16, 9999))
}
