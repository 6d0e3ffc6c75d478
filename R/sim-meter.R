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
#' dividing the hour; readings outside the simulator's hours are an error.
#' Each problem names the rows.
#'
#' Meter exports store a missing reading in many ways. The readings that
#' `rules` ([meter_rules()]) say stand for "missing" are left out, and so
#' is an hour the meter then covers only in part (a gap, the export's first
#' or last hour): one message (class
#' `bayesbem_message_readings_left_out`) counts them by reason and names
#' the first of each. Then the data's sufficiency ([data_sufficiency()]):
#' a calendar month of the readings' span with fewer than `sufficiency` of
#' its hours present (CalTRACK 2.0, 2.2.1.2: over 90 % of the hours of each
#' calendar month) is an error of class `bayesbem_error_sufficiency` naming
#' the months.
#'
#' @param simulator A `bayesbem_simulator` by hour (its `periods` hold each
#'   hour's start).
#' @param time The readings' timestamps, `POSIXct`.
#' @param y The readings: energy per interval, in the simulator's units.
#' @param stamps Whether a timestamp is the interval's `"start"` or `"end"`.
#' @param rules What stands for a missing reading: [meter_rules()], or
#'   `NULL` to take every reading as it is (a missing value is then an
#'   error).
#' @param sufficiency The share of each calendar month's hours (within the
#'   readings' span) that must be present; 0 accepts any.
#' @return A data frame with `y`, the simulator's observable inputs at
#'   those hours and `time` (the hour's start), one row per hour the meter
#'   covers; its attribute `"sufficiency"` is [data_sufficiency()]'s table.
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
field_hours <- function(simulator, time, y, stamps = c("start", "end"), rules = meter_rules(),
                        sufficiency = 0.9) {
  check_simulator(simulator)
  stamps <- match_choice(stamps)
  if (!is.null(rules) && !inherits(rules, "bayesbem_meter_rules")) {
    abort_bayesbem("{.arg rules} must be {.fn meter_rules} or {.code NULL}, not {describe_value(rules)}.",
                   "argument")
  }
  check_between(sufficiency, 0, 1)
  hours <- simulator$periods$start
  if (!inherits(hours, "POSIXct")) {
    abort_bayesbem(c("{.arg simulator} must simulate hours, with their times in {.field periods}.",
                     i = "Make it with {.code by = \"hour\"}, e.g. {.code bem_simulator(epw, by = \"hour\")}."),
                   "argument")
  }
  step <- check_readings(time, y, missing_allowed = !is.null(rules))
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
  reason <- if (is.null(rules)) factor(rep(NA_character_, length(y))) else
    missing_reasons(rules, y, start, step, attr(time, "tzone") %||% "")
  per_hour <- round(3600 / step)
  hour_of <- factor(at, levels = seq_along(hours))
  counts <- tabulate(at, nbins = length(hours))
  kept_counts <- tabulate(at[is.na(reason)], nbins = length(hours))
  sums <- as.vector(tapply(y[is.na(reason)], hour_of[is.na(reason)], sum))
  partial <- which(counts > 0L & kept_counts < per_hour & kept_counts > 0L)
  inform_left_out(reason, time, hours[partial])
  kept <- which(kept_counts == per_hour)
  field <- data.frame(y = sums[kept], simulator$x[kept, , drop = FALSE], time = hours[kept],
                      row.names = NULL)
  check_time_shift(simulator, kept, field$y)
  table <- data_sufficiency(field$time, c(hours[min(at)], hours[max(at)]))
  check_sufficiency(table, sufficiency)
  structure(field, sufficiency = table)
}

#' What stands for a missing reading in a meter export
#'
#' Exporters write a missing reading as `NA`, as a run of zeros, as a day
#' of zeros, as a spike (a reading of a meter that restarted or caught up),
#' or as a first or last reading that covers only part of its interval.
#' Each rule names one of these; [field_hours()] leaves out the readings
#' they catch and says how many, by reason.
#'
#' @param zero_hours A run of zero readings lasting at least this many
#'   hours is missing (`Inf`: never; a gas meter of a building heated only
#'   in winter reads zero for days on end).
#' @param zero_days Whether a calendar day (in the readings' time zone)
#'   whose readings sum to zero is missing.
#' @param above_median A reading over this multiple of the median of the
#'   positive readings is missing (`Inf`: never).
#' @param edges Whether the export's first and last readings are missing
#'   when under 70 % of the median reading at the same time of day (a
#'   partial interval: an hour's reading that holds half of it).
#' @return An object of class `bayesbem_meter_rules`.
#' @family simulation
#' @export
#' @examples
#' meter_rules()
#' meter_rules(zero_hours = Inf, zero_days = FALSE)  # a gas meter
meter_rules <- function(zero_hours = 24, zero_days = TRUE, above_median = 10, edges = TRUE) {
  if (!is.numeric(zero_hours) || length(zero_hours) != 1L || !isTRUE(zero_hours > 0)) {
    abort_bayesbem("{.arg zero_hours} must be a positive number of hours (or {.code Inf}), not {describe_value(zero_hours)}.",
                   "argument")
  }
  if (!is.numeric(above_median) || length(above_median) != 1L || !isTRUE(above_median > 1)) {
    abort_bayesbem("{.arg above_median} must be a number above 1 (or {.code Inf}), not {describe_value(above_median)}.",
                   "argument")
  }
  check_bool(zero_days)
  check_bool(edges)
  structure(list(zero_hours = zero_hours, zero_days = zero_days, above_median = above_median,
                 edges = edges),
            class = "bayesbem_meter_rules")
}

#' @export
print.bayesbem_meter_rules <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("Missing meter readings:",
            "  NA",
            "  zeros for {x$zero_hours} hours or more in a row",
            "{if (x$zero_days) '  a calendar day summing to zero' else ''}",
            "  over {x$above_median} x the median positive reading",
            "{if (x$edges) '  a first or last reading under 70 % of the median at its time of day' else ''}")
  invisible(x)
}

# The reason each reading is missing by `rules`, NA for a reading kept:
# the first rule that catches it, in the order of meter_rules()'s help.
missing_reasons <- function(rules, y, start, step, zone) {
  reason <- rep(NA_character_, length(y))
  whys <- character()
  mark <- function(rows, why) {
    reason[rows & is.na(reason)] <<- why
    whys <<- c(whys, why)
  }
  mark(is.na(y), "NA")
  zero <- !is.na(y) & y == 0
  runs <- rle(zero)
  long <- runs$values & runs$lengths * step / 3600 >= rules$zero_hours
  mark(rep(long, runs$lengths), sprintf("zero for %s hours or more in a row", format(rules$zero_hours)))
  if (rules$zero_days) {
    day <- format(as.POSIXct(start, origin = "1970-01-01", tz = zone), "%Y-%m-%d")
    totals <- tapply(ifelse(is.na(y), 0, y), day, sum)
    mark(day %in% names(totals)[totals == 0], "a day summing to zero")
  }
  typical <- stats::median(y[!is.na(y) & y > 0])
  if (is.finite(typical)) mark(!is.na(y) & y > rules$above_median * typical,
                               sprintf("over %s x the median reading", format(rules$above_median)))
  if (rules$edges && length(y) > 2L) {
    clock <- format(as.POSIXct(start, origin = "1970-01-01", tz = zone), "%H:%M")
    for (i in c(1L, length(y))) {
      same <- clock == clock[i] & seq_along(y) != i & !is.na(y)
      if (!is.na(y[i]) && sum(same) > 0L && y[i] < 0.7 * stats::median(y[same])) {
        mark(seq_along(y) == i, "a partial first or last reading")
      }
    }
  }
  factor(reason, levels = unique(whys))
}

# One message: the readings left out by reason (the first of each) and the
# hours then covered only in part.
inform_left_out <- function(reason, time, partial) {
  if (all(is.na(reason)) && length(partial) == 0L) {
    return(invisible())
  }
  stamp <- function(t) format(t, "%Y-%m-%d %H:%M %Z")
  why <- table(reason)
  why <- why[why > 0]
  lines <- vapply(names(why), function(r) {
    sprintf("%d reading%s: %s (the first %s)", why[[r]], if (why[[r]] > 1) "s" else "", r,
            stamp(time[which(reason == r)[1]]))
  }, character(1))
  if (length(partial) > 0L) {
    lines <- c(lines, sprintf("%d hour%s the meter then covers only in part (the first %s)",
                              length(partial), if (length(partial) > 1) "s" else "", stamp(partial[1])))
  }
  cli::cli_inform(c(i = "Left out of the field data ({sum(!is.na(reason))} of {length(reason)} reading{?s} missing by {.fn meter_rules}):",
                    stats::setNames(lines, rep("*", length(lines)))),
                  class = "bayesbem_message_readings_left_out")
}

#' The share of each calendar month's hours present in a field table
#'
#' CalTRACK (2.0, section 2.2.1.2) calls hourly data sufficient for a
#' baseline when over 90 % of the hours of each calendar month are
#' present; [field_hours()] refuses a field table below its `sufficiency`.
#'
#' @param time The hours' starts, `POSIXct` (e.g. [field_hours()]'s `time`).
#' @param span The first and last hour the data should cover (by default
#'   those of `time`); months count their hours within it.
#' @return A data frame with one row per calendar month of the span
#'   (in `time`'s time zone): `month` (`"YYYY-MM"`), `hours` in the span,
#'   `present` and their `share`.
#' @family simulation
#' @export
#' @examples
#' time <- as.POSIXct("2013-01-01", tz = "UTC") + 3600 * c(0:700, 800:1415)
#' data_sufficiency(time)
data_sufficiency <- function(time, span = range(time)) {
  if (!inherits(time, "POSIXct") || length(time) == 0L || anyNA(time)) {
    abort_bayesbem("{.arg time} must be complete {.cls POSIXct} hours, not {describe_value(time)}.",
                   "argument")
  }
  zone <- attr(time, "tzone") %||% ""
  all_hours <- seq(as.numeric(span[1]), as.numeric(span[2]), by = 3600)
  month_of <- function(t) format(as.POSIXct(t, origin = "1970-01-01", tz = zone), "%Y-%m")
  months <- unique(month_of(all_hours))
  hours <- as.vector(table(factor(month_of(all_hours), levels = months)))
  present <- as.vector(table(factor(month_of(unique(as.numeric(time))), levels = months)))
  data.frame(month = months, hours = hours, present = present, share = present / hours)
}

check_sufficiency <- function(table, sufficiency, call = rlang::caller_env()) {
  short <- table[table$share < sufficiency, , drop = FALSE]
  if (nrow(short) == 0L) {
    return(invisible())
  }
  abort_bayesbem(c("The meter covers too few hours of {nrow(short)} month{?s} to calibrate on.",
                   x = "{paste0(short$month, ': ', round(100 * short$share), ' %', collapse = ', ')} of the hours (needed: {round(100 * sufficiency)} %).",
                   i = "Train on months the meter covers, or lower {.arg sufficiency} (CalTRACK asks over 90 %); {.fn data_sufficiency} gives every month's share."),
                 "sufficiency", call = call)
}

# Timestamps sorted, distinct, of one step dividing the hour; the
# readings numeric and complete. Returns the step in seconds.
check_readings <- function(time, y, missing_allowed = FALSE, call = rlang::caller_env()) {
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
  bad <- which(is.na(time) | if (missing_allowed) is.infinite(y) else !is.finite(y))
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

#' A building's schedules estimated from its meter
#'
#' The embedded hourly model's lights, equipment and occupants follow an
#' occupancy by hour of the week, and its heating plant a timer
#' ([bem_building()]). Where the building's own schedules are unknown, its
#' meters tell them, from the mean use at each hour of the week (on the
#' clock of `time`'s time zone, summer time included):
#'
#' * `meter_occupancy()` scales that profile to 0 at the quietest hour and
#'   1 at the busiest, so that the model's schedule has the meter's weekday
#'   and weekend shape;
#' * `meter_load_fraction()` is the profile's mean over its busiest hour:
#'   the loads' mean share of their full use. Given as both
#'   `lighting_fraction` and `equipment_fraction`, with the occupancy from
#'   the same electricity meter, the model's lights and equipment follow the
#'   meter's profile, its base load included, whatever their densities, so
#'   that the densities that match the meter's level also match the
#'   amplitude of its week. With the defaults (0.6 and 0.7) a building of
#'   high base load swings more in the model than on its meter, and the
#'   likelihood favours the densities whose swing matches, below the
#'   level, leaving the level to the discrepancy;
#' * `meter_heating_schedule()` is 1 at the hours of the week when a gas
#'   (heating) meter's use is at least `on` of the way from its quietest to
#'   its busiest hour, 0 otherwise: the plant's timer. Give it the winter's
#'   readings, when the plant runs every day.
#'
#' @param time The readings' times, `POSIXct` in the building's time zone
#'   (e.g. [field_hours()]'s `time`, its zone set to the building's clock).
#' @param y The readings.
#' @param on The share of the profile's range above which the plant is on.
#' @return `meter_occupancy()` and `meter_heating_schedule()`: 168 shares
#'   from Monday 0:00, for `bem_building(occupancy = )` and
#'   `bem_building(heating_schedule = )`. `meter_load_fraction()`: one
#'   share, for `bem_building(lighting_fraction = , equipment_fraction = )`.
#' @family simulation
#' @export
#' @examples
#' time <- as.POSIXct("2013-01-07", tz = "Europe/London") + 3600 * (0:(24 * 28 - 1))
#' open <- as.integer(format(time, "%u")) <= 5 & as.integer(format(time, "%H")) %in% 8:17
#' use <- 10 + 20 * open
#' occupancy <- meter_occupancy(time, use)
#' occupancy[1:24]   # Monday
#' meter_load_fraction(time, use)   # the week's mean over its busiest hour
#' meter_heating_schedule(time, use)[1:24]
meter_occupancy <- function(time, y) {
  unit_range(week_profile(time, y))
}

#' @rdname meter_occupancy
#' @export
meter_load_fraction <- function(time, y) {
  profile <- week_profile(time, y)
  if (max(profile) <= 0) {
    abort_bayesbem(c("The readings' busiest hour of the week has a mean of {max(profile)}: no use to share out.",
                     i = "Give an electricity meter's readings."),
                   "argument")
  }
  mean(profile) / max(profile)
}

#' @rdname meter_occupancy
#' @export
meter_heating_schedule <- function(time, y, on = 0.25) {
  check_probability(on)
  as.numeric(unit_range(week_profile(time, y)) >= on)
}

# A profile scaled to 0 at its least and 1 at its most; 1 if it is flat.
unit_range <- function(profile) {
  spread <- diff(range(profile))
  if (spread == 0) rep(1, length(profile)) else (profile - min(profile)) / spread
}

# The mean reading at each of the 168 hours of the week, from Monday 0:00
# on the clock of `time`'s zone; every hour must be seen.
week_profile <- function(time, y, call = rlang::caller_env()) {
  if (!inherits(time, "POSIXct") || !is.numeric(y) || length(y) != length(time) ||
      anyNA(time)) {
    abort_bayesbem("{.arg time} and {.arg y} must be {.cls POSIXct} times and one reading each, not {describe_value(time)} and {describe_value(y)}.",
                   "argument", call = call)
  }
  week_hour <- hour_of_week(time, attr(time, "tzone") %||% "")
  profile <- as.vector(tapply(y, factor(week_hour, levels = 0:167), mean, na.rm = TRUE))
  unseen <- which(is.na(profile)) - 1L
  if (length(unseen) > 0L) {
    abort_bayesbem(c("The readings miss {length(unseen)} hour{?s} of the week.",
                     x = "Hours of the week (0 = Monday 0:00): {utils::head(unseen, 5)}.",
                     i = "Give at least a week of readings."),
                   "argument", call = call)
  }
  profile
}
