# Hourly use of a building open 8:00-18:00 on weekdays, in London's clock,
# heated below 12 C and cooled above 20 C, with AR(1) noise.
towt_problem <- function(weeks = 10, start = "2013-01-07", seed = 1) {
  withr::local_seed(seed)
  time <- as.POSIXct(start, tz = "Europe/London") + 3600 * (0:(24 * 7 * weeks - 1))
  hour <- as.integer(format(time, "%H"))
  weekday <- as.integer(format(time, "%u")) <= 5
  day <- as.numeric(difftime(time, time[1], units = "days"))
  temp <- 12 + 9 * sin(2 * pi * day / 70) + 5 * sin(2 * pi * (hour - 9) / 24) +
    stats::rnorm(length(time))
  open <- weekday & hour >= 8 & hour < 18
  noise <- as.vector(stats::filter(stats::rnorm(length(time), sd = 2), 0.5, method = "recursive"))
  y <- 30 + 40 * open + 2 * pmax(12 - temp, 0) + 3 * pmax(temp - 20, 0) * open + noise
  data.frame(y = y, temp = temp, time = time, open = open)
}

# The same regression written out by hand: one column per hour of the
# week, the temperature's part in each interval between knots, by lm().
hand_towt <- function(d, knots, rows) {
  week_hour <- (as.integer(format(d$time, "%u")) - 1L) * 24L + as.integer(format(d$time, "%H"))
  segments <- sapply(seq_len(length(knots) + 1L), function(j) {
    lo <- if (j == 1L) -Inf else knots[j - 1L]
    hi <- if (j > length(knots)) Inf else knots[j]
    ifelse(d$temp <= lo, 0, ifelse(d$temp >= hi, hi - if (j == 1L) 0 else lo,
                                   d$temp - if (j == 1L) 0 else lo))
  })
  data.frame(y = d$y, how = factor(week_hour), segments)[rows, ]
}

test_that("the TOWT baseline is the least-squares fit of its hours and knots, by mode", {
  d <- towt_problem()
  baseline <- towt_baseline(d[c("y", "temp", "time")])
  # the open hours are found occupied, the others not
  week_hour <- (as.integer(format(d$time, "%u")) - 1L) * 24L + as.integer(format(d$time, "%H"))
  open_hours <- sort(unique(week_hour[d$open]))
  expect_setequal(which(baseline$occupied) - 1L, open_hours)
  # the knots inside each mode's data (80 F and 90 F have too few hours above them)
  expect_equal(baseline$knots$unoccupied, (c(40, 55, 65) - 32) * 5 / 9)
  for (mode in names(baseline$knots)) {
    temp <- d$temp[(week_hour %in% open_hours) == (mode == "occupied")]
    k <- baseline$knots[[mode]]
    expect_gte(sum(temp < k[1]), 20)
    expect_gte(sum(temp > k[length(k)]), 20)
  }
  expect_output(print(baseline), "occupied hours of the week: 50 of 168")
  new <- towt_problem(weeks = 2, start = "2013-03-18", seed = 2)
  pred <- predict(baseline, new[c("temp", "time")], level = 0.8)
  new_hour <- (as.integer(format(new$time, "%u")) - 1L) * 24L + as.integer(format(new$time, "%H"))
  for (mode in c(TRUE, FALSE)) {
    train_rows <- (week_hour %in% open_hours) == mode
    new_rows <- (new_hour %in% open_hours) == mode
    knots <- baseline$knots[[if (mode) "occupied" else "unoccupied"]]
    by_hand <- stats::lm(y ~ ., data = hand_towt(d, knots, train_rows))
    expected <- stats::predict(by_hand, hand_towt(new, knots, new_rows),
                               interval = "prediction", level = 0.8)
    expect_equal(pred$mean[new_rows], unname(expected[, "fit"]))
    expect_equal(pred$q10[new_rows], unname(expected[, "lwr"]))
    expect_equal(pred$q90[new_rows], unname(expected[, "upr"]))
  }
  expect_identical(as.numeric(pred$time), as.numeric(new$time))
})

test_that("a month's total carries Guideline 14's uncertainty of a sum of hours", {
  d <- towt_problem()
  baseline <- towt_baseline(d[c("y", "temp", "time")])
  rows <- predict(baseline, d[c("temp", "time")])
  months <- predict(baseline, d[c("temp", "time")], by = "month")
  expect_equal(months$start, as.Date(c("2013-01-01", "2013-02-01", "2013-03-01")))
  month <- format(d$time, "%m")
  expect_equal(months$hours, as.vector(table(month)))
  expect_equal(months$mean, as.vector(tapply(rows$mean, month, sum)))
  # by hand: residuals on n - p, their lag-1 autocorrelation, n' = n (1 - rho) / (1 + rho)
  r <- d$y - rows$mean
  n <- length(r)
  p <- sum(sapply(baseline$models, function(m) length(stats::coef(m)[!is.na(stats::coef(m))])))
  rmse <- sqrt(sum(r^2) / (n - p))
  rho <- stats::cor(r[-1], r[-n])
  expect_gt(rho, 0.3)
  n_eff <- n * (1 - rho) / (1 + rho)
  u <- stats::qt(0.95, n - p) * 1.26 * rmse * sqrt(n / n_eff * (1 + 2 / n_eff) * months$hours)
  expect_equal(months$q95 - months$mean, u)
  expect_equal(months$mean - months$q5, u)
})

test_that("the hour of the week follows the building's clock, summer time included", {
  summer <- as.POSIXct("2013-07-01 09:00", tz = "Europe/London")  # a Monday, BST
  expect_equal(bayesbem:::hour_of_week(summer, "Europe/London"), 9L)
  expect_equal(bayesbem:::hour_of_week(summer, "UTC"), 8L)
  # one model of every hour when asked
  d <- towt_problem(weeks = 4)
  expect_true(all(towt_baseline(d[c("y", "temp", "time")], occupancy = "all")$occupied))
})

test_that("the TOWT baseline refuses what it cannot use, saying why", {
  d <- towt_problem(weeks = 3)
  expect_error(towt_baseline(d[c("y", "temp")]), class = "bayesbem_error_columns")
  bad <- d
  bad$time <- format(bad$time)
  expect_error(towt_baseline(bad), "POSIXct", class = "bayesbem_error_columns")
  expect_error(towt_baseline(d[c(2, 1, 3:10), ]), "Row 2", class = "bayesbem_error_periods")
  expect_error(towt_baseline(d, knots = c(20, 10)), class = "bayesbem_error_argument")
  # one week: an indicator per hour, fitted exactly
  week <- d[seq_len(168), c("y", "temp", "time")]
  expect_snapshot(towt_baseline(week, occupancy = "all"), error = TRUE)
  expect_error(towt_baseline(week), class = "bayesbem_error_too_few_rows")
  # a weekday-only training set cannot predict a weekend
  weekdays <- d[as.integer(format(d$time, "%u")) <= 5, ]
  baseline <- towt_baseline(weekdays)
  expect_error(predict(baseline, d[c("temp", "time")]), "48 hours of the week",
               class = "bayesbem_error_argument")
  expect_error(predict(baseline, d, levle = 0.5), class = "rlib_error_dots_nonempty")
})
