#' The M&V regression baseline: time of week and temperature (TOWT)
#'
#' Fits the regression an M&V programme would use in place of a calibrated
#' simulator, so that the two can be judged on the same held-out periods:
#' the time-of-week-and-temperature model of Mathieu et al. (2011), as
#' LBNL's RMV2.0, nmecr and CalTRACK's hourly method publish it. Each hour
#' of the week (in the building's clock, `time`'s time zone) is one
#' indicator; the outdoor temperature enters piecewise linearly between
#' knots (by default 40, 55, 65, 80 and 90 F, in C; a knot beyond which
#' fewer than 20 training hours of its mode lie is dropped); and occupied
#' and unoccupied hours of the week are fitted apart (an hour of the week is
#' occupied when a regression of the load on temperature, hinged at 50 and
#' 65 F, underpredicts it in more than 65 % of its hours).
#'
#' `predict()` gives each row's prediction with its ordinary least-squares
#' prediction interval (Student's t, independent residuals, the row's own
#' mode's model), or with `by = "month"` each calendar month's total with
#' the uncertainty of ASHRAE Guideline 14-2014 (Annex B, after Reddy and
#' Claridge 2000) for the sum of `m` predicted hours:
#'
#' `U = t * 1.26 * RMSE * sqrt((n / n') * (1 + 2 / n') * m)`, `n' = n (1 -
#' rho) / (1 + rho)`,
#'
#' with `RMSE` the residuals' root mean square on `n - p` degrees of
#' freedom, `rho` their lag-1 autocorrelation and 1.26 the Guideline's
#' correction for hourly models.
#'
#' @param field A data frame with the measured `y`, the outdoor
#'   temperature `temp` (C) and the hour's start `time` (`POSIXct`, in the
#'   building's time zone), one row per hour: e.g. [field_hours()]'s table.
#' @param knots Temperature knots (C) of the piecewise-linear term.
#' @param occupancy `"auto"` to find the occupied hours of the week from the
#'   data, or `"all"` for one model of every hour.
#' @return An object of class `bayesbem_towt`: the regression of each mode
#'   (`models`, [stats::lm()] fits), the occupied hours of the week
#'   (`occupied`, a logical vector of 168 from Monday 0:00), each mode's
#'   knots kept (`knots`),
#'   the residuals' `rmse`, `rho` and `p`, and the time zone.
#' @references Mathieu, J. L., Price, P. N., Kiliccote, S. and Piette, M. A.
#'   (2011). Quantifying changes in building electricity use, with
#'   application to demand response. *IEEE Transactions on Smart Grid* 2(3),
#'   507-518.
#'
#'   ASHRAE (2014). Guideline 14-2014, Measurement of energy, demand, and
#'   water savings. Annex B.
#' @family metrics
#' @export
#' @examples
#' time <- as.POSIXct("2013-01-07", tz = "UTC") + 3600 * (0:(24 * 7 * 8 - 1))
#' hour <- as.integer(format(time, "%H"))
#' temp <- 10 + 8 * sin(2 * pi * (hour - 9) / 24) + stats::rnorm(length(time), 0, 3)
#' y <- 20 + 15 * (hour %in% 8:17) + 0.8 * pmax(temp - 15, 0) + rnorm(length(time))
#' baseline <- towt_baseline(data.frame(y = y, temp = temp, time = time))
#' baseline
#' head(predict(baseline, data.frame(temp = temp, time = time)))
#' predict(baseline, data.frame(temp = temp, time = time), by = "month")
towt_baseline <- function(field, knots = celsius(c(40, 55, 65, 80, 90)),
                          occupancy = c("auto", "all")) {
  occupancy <- match_choice(occupancy)
  check_towt_table(field, c("y", "temp", "time"))
  if (!is.numeric(knots) || anyNA(knots) || is.unsorted(knots, strictly = TRUE)) {
    abort_bayesbem("{.arg knots} must be increasing temperatures (C), not {describe_value(knots)}.",
                   "argument")
  }
  zone <- attr(field$time, "tzone") %||% ""
  week_hour <- hour_of_week(field$time, zone)
  occupied <- if (occupancy == "auto") occupied_hours(field$y, field$temp, week_hour) else
    rep(TRUE, 168L)
  mode <- occupied[week_hour + 1L]
  # each mode's knots are those its own hours reach
  modes <- Filter(function(m) any(mode == m), list(occupied = TRUE, unoccupied = FALSE))
  knots <- lapply(modes, function(m) towt_knots(field$temp[mode == m], knots))
  models <- lapply(names(modes), function(m) {
    rows <- mode == modes[[m]]
    stats::lm(y ~ ., data = towt_frame(field[rows, ], week_hour[rows], knots[[m]]))
  })
  names(models) <- names(modes)
  check_towt_residuals(models, one_mode = occupancy == "all")
  residuals <- numeric(nrow(field))
  for (m in names(models)) residuals[mode == (m == "occupied")] <- stats::residuals(models[[m]])
  p <- sum(vapply(models, function(fit) fit$rank, integer(1)))
  n <- nrow(field)
  structure(list(models = models, occupied = occupied, knots = knots, zone = zone, n = n, p = p,
                 rmse = sqrt(sum(residuals^2) / (n - p)),
                 rho = stats::cor(residuals[-n], residuals[-1]),
                 mean = mean(field$y), residuals = residuals),
            class = "bayesbem_towt")
}

#' @rdname towt_baseline
#' @param object A `bayesbem_towt` baseline.
#' @param newdata A data frame with `temp` and `time` (as `field`'s) of the
#'   hours to predict.
#' @param by `NULL` for each row, or `"month"` for each calendar month's
#'   total (in the building's time zone).
#' @template args-level
#' @param ... Unused; an error if given.
#' @return `predict()`: a data frame with `time` (or the month's `start`
#'   and its `hours`), `mean`, `sd` and the interval's bounds (`q5` and
#'   `q95` at `level = 0.9`).
#' @export
predict.bayesbem_towt <- function(object, newdata, by = NULL, level = 0.9, ...) {
  rlang::check_dots_empty()
  check_towt_table(newdata, c("temp", "time"))
  check_probability(level)
  week_hour <- hour_of_week(newdata$time, object$zone)
  mode <- object$occupied[week_hour + 1L]
  mean <- sd <- half <- numeric(nrow(newdata))
  t_quantile <- function(df) stats::qt(interval_probs(level)[2], df)
  for (m in names(object$models)) {
    rows <- mode == (m == "occupied")
    if (!any(rows)) next
    model <- object$models[[m]]
    frame <- towt_frame(newdata[rows, , drop = FALSE], week_hour[rows], object$knots[[m]])
    check_hours_seen(frame$hour, model, m)
    p <- stats::predict(model, frame, se.fit = TRUE)
    mean[rows] <- p$fit
    sd[rows] <- sqrt(p$se.fit^2 + p$residual.scale^2)
    half[rows] <- t_quantile(p$df) * sd[rows]
  }
  if (is.null(by)) {
    out <- data.frame(time = newdata$time, mean = mean, sd = sd)
  } else {
    match_choice(by, "month")
    out <- towt_month_totals(object, newdata$time, mean)
    half <- t_quantile(object$n - object$p) * out$sd
  }
  bounds <- out$mean + cbind(-half, half)
  colnames(bounds) <- quantile_names(interval_probs(level))
  cbind(out, bounds)
}

# Each calendar month's total of predicted hours, with Guideline 14's
# uncertainty of a sum of m hours (see the help): its sd is U / t.
towt_month_totals <- function(object, time, mean) {
  month <- format(time, "%Y-%m", tz = object$zone)
  months <- unique(month)
  n <- object$n
  n_eff <- n * (1 - object$rho) / (1 + object$rho)
  hours <- as.vector(table(factor(month, levels = months)))
  data.frame(start = as.Date(paste0(months, "-01")), hours = hours,
             mean = as.vector(tapply(mean, factor(month, levels = months), sum)),
             sd = 1.26 * object$rmse * sqrt((n / n_eff) * (1 + 2 / n_eff) * hours))
}

#' @export
print.bayesbem_towt <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("TOWT baseline (time of week and temperature) of {x$n} hours, {x$p} coefficients",
            "  occupied hours of the week: {sum(x$occupied)} of 168",
            "  temperature knots (C): {paste(names(x$knots), vapply(x$knots, function(k) paste(round(k, 1), collapse = ', '), character(1)), sep = ' ', collapse = '; ')}",
            "  CV(RMSE) {format(round(100 * x$rmse / x$mean, 1))} %, residuals' lag-1 autocorrelation {format(round(x$rho, 2))}")
  invisible(x)
}

celsius <- function(fahrenheit) (fahrenheit - 32) * 5 / 9

# The knots with at least `min_rows` temperatures below the lowest and
# above the highest: outer knots without data are dropped one by one.
towt_knots <- function(temp, knots, min_rows = 20L) {
  while (length(knots) > 0L && sum(temp < knots[1]) < min_rows) knots <- knots[-1]
  while (length(knots) > 0L && sum(temp > knots[length(knots)]) < min_rows) {
    knots <- knots[-length(knots)]
  }
  knots
}

# The piecewise-linear temperature terms: column j is the part of the
# temperature in [knot_{j-1}, knot_j] (the first below knot_1, the last
# above the last knot), so their sum is the temperature and each slope
# holds between two knots (Mathieu et al. 2011, eq. 2).
temperature_terms <- function(temp, knots) {
  edges <- c(-Inf, knots, Inf)
  terms <- vapply(seq_len(length(knots) + 1L), function(j) {
    lower <- if (j == 1L) 0 else edges[j]
    pmin(pmax(temp, edges[j]), edges[j + 1L]) - lower
  }, numeric(length(temp)))
  matrix(terms, nrow = length(temp), dimnames = list(NULL, paste0("temp", seq_len(ncol(terms)))))
}

towt_frame <- function(d, week_hour, knots) {
  frame <- data.frame(hour = factor(week_hour, levels = 0:167),
                      temperature_terms(d$temp, knots))
  if (!is.null(d$y)) frame$y <- d$y
  frame
}

# Occupied hours of the week: those whose load a regression on temperature
# hinged at 50 and 65 F underpredicts in more than 65 % of their hours
# (Mathieu et al. 2011); all hours when fewer than 3 would be.
occupied_hours <- function(y, temp, week_hour) {
  hinge <- cbind(pmin(temp - celsius(50), 0), pmax(temp - celsius(65), 0))
  above <- stats::residuals(stats::lm(y ~ hinge)) > 0
  share <- tapply(above, factor(week_hour, levels = 0:167), mean)
  occupied <- !is.na(share) & share > 0.65
  if (sum(occupied) <= 2L) rep(FALSE, 168L) else occupied
}

check_towt_table <- function(d, cols, arg = rlang::caller_arg(d), call = rlang::caller_env()) {
  if (!is.data.frame(d) || !all(cols %in% names(d))) {
    abort_bayesbem(c("{.arg {arg}} must be a data frame with columns {.field {cols}}.",
                     x = if (is.data.frame(d)) "Its columns are {.field {names(d)}}." else "It is {.obj_type_friendly {d}}."),
                   "columns", call = call)
  }
  if (!inherits(d$time, "POSIXct")) {
    abort_bayesbem(c("Column {.field time} of {.arg {arg}} must be {.cls POSIXct}: each hour's start.",
                     i = "Parse it in the building's time zone, e.g. {.code as.POSIXct(x, tz = \"Europe/London\")}."),
                   "columns", call = call)
  }
  steps <- diff(as.numeric(d$time))
  bad <- utils::head(which(steps <= 0 | steps %% 3600 != 0) + 1L, 5)
  if (length(bad) > 0L) {
    abort_bayesbem(c("Rows of {.arg {arg}} must be hours in order (gaps are allowed).",
                     x = "{cli::qty(length(bad))}Row{?s} {bad} {cli::qty(length(bad))}{?does/do} not start a later hour than the row above."),
                   "periods", call = call)
  }
  check_numeric_complete(d, setdiff(cols, "time"), arg, call = call)
}

# A mode whose regression has as many terms as hours (one week of
# training: one hour per indicator) fits them exactly, leaving no residual
# to estimate its uncertainty from.
check_towt_residuals <- function(models, one_mode = FALSE, call = rlang::caller_env()) {
  left <- vapply(models, stats::df.residual, numeric(1))
  if (any(left < 1)) {
    m <- names(models)[left < 1][1]
    # with occupancy = "all" there is no mode to name
    hours <- if (one_mode) "hours" else paste(m, "hours")
    abort_bayesbem(c("The baseline's {hours} are fewer than its terms: the regression fits them exactly and leaves no residual to estimate its uncertainty from.",
                     x = "{nrow(models[[m]]$model)} {hours} for {models[[m]]$rank} terms (one per hour of the week and the temperature segments).",
                     i = "Train on more than one week of every hour of the week; M&V practice takes a year."),
                   "too_few_rows", call = call)
  }
}

# New rows may only be at hours of the week the mode's model was fitted on.
check_hours_seen <- function(hour, model, mode, call = rlang::caller_env()) {
  seen <- model$xlevels$hour
  unseen <- setdiff(as.character(unique(hour)), seen)
  if (length(unseen) > 0L) {
    abort_bayesbem(c("{.arg newdata} has {length(unseen)} hour{?s} of the week the baseline's {mode} hours never saw.",
                     x = "Hours of the week (0 = Monday 0:00): {utils::head(unseen, 5)}.",
                     i = "Train on at least one full week of every hour you predict."),
                   "argument", call = call)
  }
}
