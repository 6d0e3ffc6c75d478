# The observation noise of periods of different lengths (koh_data(),
# "Noise"). A period's total sums its days' errors; independent days give
#   var(e_i) = w_i / lambda_e,  w_i = days_i / mean(days over the field rows),
# so 1 / lambda_e is the noise variance of a field period of average length.
# Periods of one length (calendar months, days, hours) have no input
# `days`, and every w_i is 1: the paper's model.
#
# What the noise model reads of the data: each row's weight w_i, the
# AR(1) segments of consecutive rows and the rows' calendar months; its
# covariance and draws are in R/gp-noise.R.

# The mean length of the field's periods, the reference of every weight
# (NULL when the rows carry no `days`), kept in the data's scaling so that
# new periods (predictions, scenarios) are weighed on the fit's reference.
noise_reference <- function(x_raw) {
  if ("days" %in% colnames(x_raw)) mean(x_raw[, "days"]) else NULL
}

# Each row's w_i for a table of inputs in physical units (the field's by
# default), from its `days`, on the fit's reference.
noise_weights <- function(data, x = data$field) {
  period_weights(x, data$scaling$days)
}

# w_i of the periods of a table of inputs, on the mean of its own `days`
# unless a reference is given.
period_weights <- function(x, reference = noise_reference(x)) {
  if (is.null(reference)) rep(1, NROW(x)) else x[, "days"] / reference
}

# AR(1) noise (R/gp-noise.R) correlates consecutive periods: rows in order
# whose times are one step apart, the step the median difference; a gap or
# a step back starts a new segment.

# The segment of each row (1, 2, ...) from the rows' times (Date or POSIXct).
noise_segments <- function(times) {
  gaps <- diff(as.numeric(times))
  if (length(gaps) == 0L) {
    return(rep(1L, length(times)))
  }
  step <- stats::median(gaps)
  cumsum(c(TRUE, !(step > 0 & abs(gaps - step) <= 1e-6 * step)))
}

# A data set's field times (its period column), NULL without one.
data_times <- function(data) {
  period <- data$names$period
  if (!is.null(period)) data$field[[period]]
}

# The segments of a data set's field rows from its period column, NULL
# without one.
data_segments <- function(data) {
  times <- data_times(data)
  if (!is.null(times)) noise_segments(times)
}

# The segments of a data set's field rows, from its period column (an
# error without one: which rows follow which is not in the inputs).
field_segments <- function(data, call = rlang::caller_env()) {
  noise_segments(field_times(data, "AR(1) noise", call = call))
}

# A data set's field times (its period column), which `what` needs: an
# error without them.
field_times <- function(data, what, call = rlang::caller_env()) {
  times <- data_times(data)
  if (is.null(times)) {
    abort_bayesbem(c("{what} needs the times of the field rows.",
                     i = "Give the field a {.cls POSIXct} or {.cls Date} column (as {.fn field_hours} does: {.field time}), or name it with {.arg period} in {.fn koh_data}."),
                   "argument", call = call)
  }
  times
}

# A shift per calendar month (R/gp-noise.R) is shared by the rows of a
# month, in the time zone of the rows' times.

# The calendar month ("2019-10") of each time (Date, or POSIXct in its own
# time zone).
period_months <- function(times) {
  if (inherits(times, "POSIXct")) {
    return(format(times, "%Y-%m", tz = attr(times, "tzone") %||% ""))
  }
  format(times, "%Y-%m")
}

# The months of a data set's field rows, from its period column (an error
# without one).
field_months <- function(data, call = rlang::caller_env()) {
  period_months(field_times(data, "A shift per month", call = call))
}
