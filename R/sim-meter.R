#' Interval meter data as field data of an hourly simulator
#'
#' Smart (AMI) meters give energy per interval (an hour, 15 or 30 minutes)
#' with a timestamp. `field_hours()` sums the intervals into the hours of a
#' simulator by hour (e.g. `bem_simulator(epw, by = "hour")` or
#' `eplus_simulator(..., by = "hour")`) and returns the field table of
#' those hours: the measured `y`, the hours' observable inputs and their
#' `time`, ready for [koh_data()] and [calibrate()].
#'
#' Timestamps are instants (`POSIXct` in any time zone, with or without
#' daylight-saving time), compared with the simulator's hours, which run in
#' the weather file's standard time: a meter in local time with
#' daylight-saving time is matched without shifting any hour. Meters stamp
#' an interval by its start or by its end (`stamps`): by its end, a reading
#' stamped 13:00 is the hour from 12:00. A wrong convention shifts every
#' reading by one interval, which a calibration would absorb in the
#' discrepancy; so the hours' use is compared with the simulator's at its
#' initial parameters one and two hours earlier and later, and a clearly
#' better match at another lag is a warning of class
#' `bayesbem_warning_time_shift` that names it.
#'
#' Readings must be sorted and distinct, and the intervals of one length
#' dividing the hour; an hour the meter covers only in part (a gap, the
#' file's first or last hour) is left out with a message; readings outside
#' the simulator's hours are an error. Each problem names the rows.
#'
#' @param simulator A `bayesbem_simulator` by hour (its `periods` hold each
#'   hour's start).
#' @param time The readings' timestamps, `POSIXct`.
#' @param y The readings: energy per interval, in the simulator's units.
#' @param stamps Whether a timestamp is the interval's `"start"` or `"end"`.
#' @return A data frame with `y`, the simulator's observable inputs at
#'   those hours and `time` (the hour's start), one row per hour the meter
#'   covers.
#' @family simulation
#' @export
#' @examples
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' sim <- bem_simulator(epw, by = "hour")
#' # a week of 15-minute readings, stamped at the end of each interval
#' time <- as.POSIXct("2013-03-04 00:15", tz = "America/Denver") + 900 * (0:671)
#' use <- simulate_design(sim, data.frame(equipment_power_density = 15))$eta
#' hours <- as.numeric(difftime(time - 900, sim$periods$start[1], units = "hours"))
#' y <- use[floor(hours) + 1] / 4
#' field <- field_hours(sim, time, y, stamps = "end")
#' head(field)
field_hours <- function(simulator, time, y, stamps = c("start", "end")) {
  check_simulator(simulator)
  stamps <- match_choice(stamps)
  hours <- simulator$periods$start
  if (!inherits(hours, "POSIXct")) {
    abort_bayesbem(c("{.arg simulator} must simulate hours, with their times in {.field periods}.",
                     i = "Make it with {.code by = \"hour\"}, e.g. {.code bem_simulator(epw, by = \"hour\")}."),
                   "argument")
  }
  step <- check_readings(time, y)
  # each reading's interval start, on the simulator's clock
  start <- as.numeric(time) - if (stamps == "end") step else 0
  hour_start <- as.numeric(hours)
  at <- findInterval(start, hour_start)
  outside <- which(at == 0L | start >= hour_start[length(hour_start)] + 3600)
  if (length(outside) > 0L) {
    first <- utils::head(outside, 5)
    abort_bayesbem(c("{length(outside)} reading{?s} fall{?s/} outside the simulator's hours.",
                     x = "{cli::qty(length(first))}Row{?s} {first}{if (length(outside) > 5) ', ...' else ''}; the simulator covers {format(hours[1])} to {format(hours[length(hours)] + 3600)}.",
                     i = "Keep the readings of the weather file's period, or simulate the readings' year."),
                   "periods")
  }
  per_hour <- round(3600 / step)
  counts <- tabulate(at, nbins = length(hours))
  sums <- as.vector(tapply(y, factor(at, levels = seq_along(hours)), sum))
  partial <- which(counts > 0L & counts < per_hour)
  if (length(partial) > 0L) {
    cli::cli_inform(c(i = "Left out {length(partial)} hour{?s} the meter covers only in part (the first: {format(hours[partial[1]], '%Y-%m-%d %H:%M %Z')})."),
                    class = "bayesbem_message_partial_hours")
  }
  kept <- which(counts == per_hour)
  field <- data.frame(y = sums[kept], simulator$x[kept, , drop = FALSE], time = hours[kept],
                      row.names = NULL)
  check_time_shift(simulator, kept, field$y)
  field
}

# Timestamps sorted, distinct, of one step dividing the hour; the
# readings numeric and complete. Returns the step in seconds.
check_readings <- function(time, y, call = rlang::caller_env()) {
  if (!inherits(time, "POSIXct")) {
    abort_bayesbem(c("{.arg time} must be {.cls POSIXct} timestamps.",
                     x = "It is {.obj_type_friendly {time}}.",
                     i = "Parse them with their time zone, e.g. {.code as.POSIXct(x, tz = \"America/Denver\")}."),
                   "periods", call = call)
  }
  if (!is.numeric(y) || length(y) != length(time)) {
    abort_bayesbem("{.arg y} must be one number per timestamp ({length(time)}), not {describe_value(y)}.",
                   "argument", call = call)
  }
  bad <- which(is.na(time) | !is.finite(y))
  if (length(bad) > 0L) {
    abort_bayesbem(c("Readings without a time or a value.", x = "Row{?s} {utils::head(bad, 5)}.",
                     i = "Remove them, or fill them before calibrating."),
                   "missing", call = call)
  }
  gaps <- diff(as.numeric(time))
  # the rows (first five) where the readings break a rule
  abort_rows <- function(rows, what, x, i) {
    rows <- utils::head(rows + 1L, 5)
    abort_bayesbem(c(what, x = paste("{cli::qty(length(rows))}Row{?s} {rows} {cli::qty(length(rows))}", x), i = i),
                   "periods", call = call)
  }
  if (any(gaps == 0)) {
    abort_rows(which(gaps == 0), "Duplicated timestamps.", "repeat{?s/} the row above.",
               "Keep one reading per interval (a daylight-saving change in local time without a zone makes two 1:00s: parse with the zone).")
  }
  if (any(gaps < 0)) {
    abort_rows(which(gaps < 0), "Timestamps out of order.", "come{?s/} before the row above.",
               "Sort the readings by time.")
  }
  step <- if (length(gaps) > 0L) min(gaps) else 3600
  if (3600 %% step != 0 || any(gaps %% step != 0)) {
    abort_rows(which(gaps %% step != 0),
               "Readings must be at intervals of one length that divides the hour (15, 30 or 60 minutes).",
               "break{?s/} the shortest interval.", "Sum or drop the readings of other intervals.")
  }
  step
}

# A clear shift between the meter's hours and the simulator's: the use
# correlates better with the simulator's at its initial parameters some
# hours earlier or later (of lags -2 to 2, by more than 0.05 and with the
# best correlation above 0.5).
check_time_shift <- function(simulator, kept, y) {
  simulated <- simulator$fun(initial_values(simulator$parameters), simulator$x)
  if (is.data.frame(simulated)) simulated <- simulated[[1]]
  lags <- -2:2
  cors <- vapply(lags, function(lag) {
    at <- kept + lag
    ok <- at >= 1L & at <= length(simulated)
    suppressWarnings(stats::cor(y[ok], simulated[at[ok]]))
  }, numeric(1))
  # (constant use, or a constant simulator, correlates with nothing)
  if (!all(is.finite(cors))) {
    return(invisible())
  }
  best <- which.max(cors)
  if (lags[best] != 0L && cors[best] > 0.5 && cors[best] > cors[lags == 0L] + 0.05) {
    warn_bayesbem(c("The meter's use follows the simulator's {abs(lags[best])} hour{?s} {if (lags[best] > 0) 'later' else 'earlier'} better than at the same hour (correlation {round(cors[best], 2)} against {round(cors[lags == 0L], 2)}).",
                    i = "Check the timestamps: do they mark each interval's end ({.code stamps = \"end\"}) or its start, and in which time zone?"),
                  "time_shift")
  }
}

#' Calendar covariates of a simulator's periods
#'
#' What the weather does not say about a period: for hours, the `hour` of
#' the day, whether it falls on a `weekend` and on a `holiday`; for days
#' and longer periods (bills), the share of their days that are weekend
#' days and holidays. Give them as discrepancy candidates
#' (`explain_discrepancy(covariates = )`, `extend()`), or, for hours and
#' days, bind them to the field table as observable inputs.
#'
#' @param simulator A `bayesbem_simulator` with `periods` (the
#'   weather-driven simulators).
#' @param holidays `Date`s of holidays (e.g. the local public holidays of
#'   the years simulated); `NULL` for none.
#' @return A data frame, one row per period of the simulator: `hour` (for
#'   hours only), `weekend` and `holiday` (0/1 for hours and days, shares
#'   of days for longer periods).
#' @family simulation
#' @export
#' @examples
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' new_year <- as.Date(c("2013-01-01", "2013-12-25"))
#' head(calendar_covariates(bem_simulator(epw), holidays = new_year))
#' calendar_covariates(bem_simulator(epw, by = "hour"), holidays = new_year)[1:3, ]
calendar_covariates <- function(simulator, holidays = NULL) {
  check_simulator(simulator)
  periods <- simulator$periods
  if (is.null(periods)) {
    abort_bayesbem(c("{.arg simulator} has no dated periods.",
                     i = "Make it from weather: {.fn bem_simulator} or {.fn eplus_simulator}."),
                   "argument")
  }
  if (!is.null(holidays) && (!inherits(holidays, "Date") || anyNA(holidays))) {
    abort_bayesbem("{.arg holidays} must be {.cls Date}s, not {describe_value(holidays)}.",
                   "argument")
  }
  if (inherits(periods$start, "POSIXct")) {
    # the hour's calendar day and time in the weather's own (standard) time
    zone <- attr(periods$start, "tzone") %||% ""
    day <- as.Date(format(periods$start, "%Y-%m-%d", tz = zone))
    return(data.frame(hour = as.integer(format(periods$start, "%H", tz = zone)),
                      weekend = as.integer(format(day, "%u") %in% c("6", "7")),
                      holiday = as.integer(day %in% holidays)))
  }
  shares <- t(vapply(seq_len(nrow(periods)), function(i) {
    days <- seq(periods$start[i], periods$end[i], by = "day")
    c(weekend = mean(format(days, "%u") %in% c("6", "7")), holiday = mean(days %in% holidays))
  }, numeric(2)))
  as.data.frame(shares)
}
