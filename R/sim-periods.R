# Periods from the data: each measurement's first and last day (a bill's
# dates), checked, and the days of a weather file each one holds.

# `periods` as a data frame of Dates `start` and `end` (inclusive), in
# order, neither overlapping nor ending before they start; gaps (a missing
# bill) are allowed. Every problem names its rows.
check_periods <- function(periods, arg = rlang::caller_arg(periods), call = rlang::caller_env()) {
  if (!is.data.frame(periods) || !all(c("start", "end") %in% names(periods))) {
    abort_bayesbem(c("{.arg {arg}} must be a data frame with columns {.field start} and {.field end}: each period's first and last day.",
                     x = if (is.data.frame(periods)) "Its columns are {.field {names(periods)}}." else "It is {.obj_type_friendly {periods}}.",
                     i = "E.g. {.code data.frame(start = as.Date(\"2013-01-05\"), end = as.Date(\"2013-02-03\"))}."),
                   "columns", call = call)
  }
  if (nrow(periods) == 0L) {
    abort_bayesbem("{.arg {arg}} has no rows.", "periods", call = call)
  }
  days <- lapply(c(start = "start", end = "end"), function(col) as_days(periods[[col]], col, arg, call))
  abort_rows <- function(rows, what, fix) abort_period_rows(rows, what, fix, arg, call)
  backwards <- which(days$end < days$start)
  if (length(backwards) > 0L) {
    abort_rows(backwards, c("ends before it starts", "end before they start"), "Give each period's first day as {.field start} and its last as {.field end}.")
  }
  n <- nrow(periods)
  if (n > 1L) {
    unsorted <- which(days$start[-1] < days$start[-n]) + 1L
    if (length(unsorted) > 0L) {
      abort_rows(unsorted, c("starts before the period above it", "start before the periods above them"), "Sort the periods by their start, e.g. {.code periods[order(periods$start), ]}.")
    }
    overlap <- which(days$start[-1] <= days$end[-n]) + 1L
    if (length(overlap) > 0L) {
      abort_rows(overlap, c("overlaps the period above it", "overlap the periods above them"), "Periods are separate readings: the next starts after the day the last ends (the same day twice counts it twice).")
    }
  }
  data.frame(start = days$start, end = days$end)
}

# The error naming the rows of periods `arg` that break a rule; `what`:
# the singular's and the plural's verb phrase.
abort_period_rows <- function(rows, what, fix, arg, call) {
  what <- what[min(length(rows), 2L)]
  abort_bayesbem(c("{cli::qty(length(rows))}Row{?s} {rows} of {.arg {arg}} {what}.", i = fix),
                 "periods", call = call)
}

# A simulator's `periods`, one row per row of its inputs (`n`): days
# (`Date`s, each period's first and last, checked as check_periods() does)
# or instants (`POSIXct`, each period's start and the next's: an hour's
# end is the next hour's start), in order, none backwards or overlapping.
check_simulator_periods <- function(periods, n, call = rlang::caller_env()) {
  if (!is.data.frame(periods) || !all(c("start", "end") %in% names(periods)) ||
      nrow(periods) != n) {
    abort_bayesbem(c("{.arg periods} must be a data frame with {.field start} and {.field end}, one row per row of {.arg x} ({n}).",
                     x = "It is {describe_value(periods)}."),
                   "periods", call = call)
  }
  if (!inherits(periods$start, "POSIXct")) {
    days <- check_periods(periods, call = call)
    return(cbind(days, periods[setdiff(names(periods), c("start", "end"))]))
  }
  if (!inherits(periods$end, "POSIXct") || anyNA(periods$start) || anyNA(periods$end)) {
    abort_bayesbem(c("{.field start} and {.field end} of {.arg periods} must both be complete {.cls POSIXct} times.",
                     i = "Give each period's start and the next period's start, e.g. an hour's and the next hour's."),
                   "periods", call = call)
  }
  start <- as.numeric(periods$start)
  end <- as.numeric(periods$end)
  abort_rows <- function(rows, what, fix) {
    abort_period_rows(utils::head(rows, 5), what, fix, "periods", call)
  }
  if (any(end <= start)) {
    abort_rows(which(end <= start), c("ends no later than it starts", "end no later than they start"),
               "Give each period's start as {.field start} and the next period's start as {.field end}.")
  }
  later <- seq_len(n)[-1]
  if (any(start[later] < start[-n])) {
    abort_rows(later[start[later] < start[-n]],
               c("starts before the period above", "start before the periods above them"),
               "Sort the periods by their start.")
  }
  if (any(start[later] < end[-n])) {
    abort_rows(later[start[later] < end[-n]],
               c("starts before the period above ends", "start before the periods above them end"),
               "Periods are separate readings: the next starts where the last ends, or later.")
  }
  periods
}

# The hour of the week, 0 (Monday 0:00) to 167, on the clock of `zone`
# (with its summer time: a building's hours follow its clock).
hour_of_week <- function(time, zone) {
  (as.integer(format(time, "%u", tz = zone)) - 1L) * 24L + as.integer(format(time, "%H", tz = zone))
}

# A column of dates as Dates: Date, POSIXct (its calendar day) or
# "YYYY-MM-DD" strings; anything else, or a missing date, names its rows.
as_days <- function(v, col, arg, call) {
  days <- if (inherits(v, "Date")) {
    v
  } else if (inherits(v, "POSIXct")) {
    as.Date(format(v, "%Y-%m-%d"))
  } else if (is.character(v)) {
    as.Date(v, format = "%Y-%m-%d")
  } else {
    abort_bayesbem(c("Column {.field {col}} of {.arg {arg}} must hold dates.",
                     x = "It is {.obj_type_friendly {v}}.",
                     i = "Give {.cls Date}s, e.g. {.code as.Date(\"2013-01-05\")}, or {.val YYYY-MM-DD} strings."),
                   "periods", call = call)
  }
  bad <- which(is.na(days))
  if (length(bad) > 0L) {
    abort_bayesbem(c("Column {.field {col}} of {.arg {arg}} has missing or unreadable dates.",
                     x = "{cli::qty(length(bad))}Row{?s} {bad}{if (is.character(v)) paste0(': ', paste0('\"', utils::head(v[bad], 3), '\"', collapse = ', ')) else ''}.",
                     i = "Give every period both dates, as {.val YYYY-MM-DD}."),
                   "periods", call = call)
  }
  days
}

# The calendar dates of weather records or days (columns `year`, `month`,
# `day`).
record_dates <- function(d) as.Date(sprintf("%04d-%02d-%02d", d$year, d$month, d$day))

# Whether dates are those of actual weather (their days consecutive), not a
# typical year's (months from different years).
actual_weather <- function(dates) all(diff(as.numeric(unique(dates))) == 1)

# The period of each day of a weather file (`days`: its days in order, with
# `year`, `month` and `day`): the row of `periods` holding it, NA for days
# in none. A file of actual weather (consecutive dates) is matched by date;
# a typical-year file (months from different years) by month and day (it
# has no 29 February: a period holding one holds a day less), so periods
# of two years must not fall on the same days of it. A period with a day
# the file lacks is an error naming its rows.
period_of_days <- function(days, periods, path, call = rlang::caller_env()) {
  dates <- record_dates(days)
  actual <- actual_weather(dates)
  key <- function(d) if (actual) format(d, "%Y-%m-%d") else sub("02-29$", "02-28", format(d, "%m-%d"))
  day_keys <- key(dates)
  period <- rep(NA_integer_, length(dates))
  missing <- integer(0)
  for (i in seq_len(nrow(periods))) {
    wanted <- unique(key(seq(periods$start[i], periods$end[i], by = "day")))
    at <- match(wanted, day_keys)
    if (anyNA(at)) missing <- c(missing, i)
    at <- at[!is.na(at)]
    taken <- unique(period[at][!is.na(period[at])])
    if (length(taken) > 0L) {
      abort_bayesbem(c("Periods {taken[1]} and {i} of {.arg periods} fall on the same days of the typical year in {.file {path}}.",
                       i = "A typical year holds each day once: calibrate one year of periods, or use the actual weather of their dates."),
                     "periods", call = call)
    }
    period[at] <- i
  }
  if (length(missing) > 0L) {
    held <- if (actual) paste(format(range(dates)), collapse = " to ") else "a typical year (matched by month and day)"
    abort_bayesbem(c("{cli::qty(length(missing))}Period{?s} {missing} of {.arg periods} {cli::qty(length(missing))}hold{?s/} days the weather file lacks.",
                     x = "{.file {path}} covers {held}.",
                     i = "Use the weather of the periods' dates, or leave those periods out."),
                   "periods", call = call)
  }
  period
}

# The measurements' periods as a list of checked tables: one table for
# every output, or a list of tables named by output (each meter read on
# its own days).
check_output_periods <- function(periods, output, call = rlang::caller_env()) {
  if (is.data.frame(periods)) {
    return(list(check_periods(periods, call = call)))
  }
  if (!is.list(periods) || is.null(names(periods)) || !setequal(names(periods), output) ||
      anyDuplicated(names(periods))) {
    abort_bayesbem(c("{.arg periods} must be a table of periods, or a list of them named by output.",
                     x = "It is {describe_value(periods)}{if (is.list(periods) && !is.null(names(periods))) paste0(' named ', paste(names(periods), collapse = ', ')) else ''}.",
                     i = "The outputs are {.val {output}}; e.g. {.code list({output[1]} = bills, ...)}."),
                   "periods", call = call)
  }
  lapply(stats::setNames(output, output), function(k) {
    check_periods(periods[[k]], arg = sprintf("periods$%s", k), call = call)
  })
}

# The distinct periods of several tables, by start then end: a simulator of
# several meters read on other days runs every meter over all of them.
union_periods <- function(tables) {
  all <- unique(do.call(rbind, unname(tables)))
  all <- all[order(all$start, all$end), , drop = FALSE]
  rownames(all) <- NULL
  all
}
