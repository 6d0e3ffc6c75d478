# The hourly embedded model of 2013 and its use at one setting, by hour.
hourly_truth <- local({
  made <- NULL
  function() {
    if (is.null(made)) {
      sim <- bem_simulator(shipped_epw(2013), by = "hour")
      design <- data.frame(equipment_power_density = 15, infiltration_per_exterior_area = 8e-4)
      made <<- list(sim = sim, use = simulate_design(sim, design)$eta)
    }
    made
  }
})

# The simulator's hour (row) of each instant.
hour_of <- function(sim, time) {
  floor(as.numeric(difftime(time, sim$periods$start[1], units = "hours"))) + 1
}

test_that("15-minute readings stamped at their end sum to the simulator's hours, across DST", {
  truth <- hourly_truth()
  sim <- truth$sim
  # 8 to 12 March 2013 in Denver, whose clocks moved from 2:00 to 3:00 on the 10th
  time <- as.POSIXct("2013-03-08 00:15", tz = "America/Denver") + 900 * (0:(4 * 24 * 4 - 1))
  y <- truth$use[hour_of(sim, time - 900)] / 4
  field <- field_hours(sim, time, y, stamps = "end")
  rows <- hour_of(sim, field$time)
  expect_equal(field$y, truth$use[rows])
  expect_equal(field[names(sim$x)], sim$x[rows, ], ignore_attr = TRUE)
  # every hour is one of the weather's, none repeated or skipped at the change
  expect_equal(diff(rows), rep(1, length(rows) - 1))
  # (local midnight is 0:00 standard time until the change, 23:00 after it)
  expect_equal(format(field$time[1], "%H:%M"), "00:00")
  expect_equal(nrow(field), 4 * 24)
  # an hour covered in part is left out, with a message
  expect_message(part <- field_hours(sim, time[-1], y[-1], stamps = "end"),
                 "1 hour the meter then covers only in part",
                 class = "bayesbem_message_readings_left_out")
  expect_equal(part, field[-1, ], ignore_attr = TRUE)
})

test_that("readings shifted by an hour are found, not absorbed", {
  truth <- hourly_truth()
  sim <- truth$sim
  time <- as.POSIXct("2013-07-01 01:00", tz = "America/Denver") + 3600 * (0:(24 * 14 - 1))
  y <- truth$use[hour_of(sim, time - 3600)]
  expect_no_warning(field_hours(sim, time, y, stamps = "end"))
  # constant readings correlate with nothing: no verdict
  expect_no_warning(field_hours(sim, time, rep(1, length(time)), stamps = "end"))
  expect_warning(field_hours(sim, time, y, stamps = "start"), "1 hour earlier",
                 class = "bayesbem_warning_time_shift")
  expect_warning(field_hours(sim, time - 3600, y, stamps = "end"), "1 hour later",
                 class = "bayesbem_warning_time_shift")
})

test_that("bad readings are classed errors that name the rows", {
  withr::local_options(cli.num_colors = 1)
  truth <- hourly_truth()
  sim <- truth$sim
  time <- as.POSIXct("2013-07-01 00:00", tz = "UTC") + 3600 * (0:5)
  y <- rep(1, 6)
  expect_snapshot(error = TRUE, {
    field_hours(sim, time[c(1, 3, 2, 4:6)], y)
    field_hours(sim, time[c(1, 2, 2, 4:6)], y)
    field_hours(sim, time + c(0, 0, 0, 1200, 1200, 1200), y)
    field_hours(sim, format(time), y)
    field_hours(sim, time + 365 * 86400, y)
    field_hours(bem_simulator(shipped_epw(2013)), time, y)
  })
  expect_error(field_hours(sim, time, y[-1]), class = "bayesbem_error_argument")
  expect_error(field_hours(sim, time, replace(y, 2, NA), rules = NULL),
               class = "bayesbem_error_missing")
  expect_error(field_hours(sim, time, y, rules = list()), class = "bayesbem_error_argument")
})

test_that("readings that stand for missing are left out, counted by reason in one message", {
  truth <- hourly_truth()
  sim <- truth$sim
  # four weeks of hourly readings in November, stamped at their start
  time <- as.POSIXct("2013-11-01 00:00", tz = "Etc/GMT+7") + 3600 * (0:(24 * 28 - 1))
  use <- truth$use[hour_of(sim, time)]
  y <- use
  y[1] <- use[1] / 2                       # the export's first hour: half a reading
  y[50:52] <- NA                           # missing
  y[24 * 10 + 1:24] <- 0                   # a day of zeros (11 November)
  y[24 * 20 + 3:8] <- 0                    # six hours of zeros: kept at zero_hours = 24
  y[400] <- 50 * stats::median(use)        # a spike
  expect_snapshot(field <- field_hours(sim, time, y))
  kept <- hour_of(sim, field$time)
  left_out <- c(1, 50:52, 24 * 10 + 1:24, 400)
  expect_setequal(setdiff(hour_of(sim, time), kept), hour_of(sim, time)[left_out])
  expect_equal(field$y, y[-left_out])
  # the same readings, with the zero runs kept and a shorter zero rule
  rules <- meter_rules(zero_hours = 6, zero_days = FALSE, above_median = Inf, edges = FALSE)
  expect_message(other <- field_hours(sim, time, y, rules = rules),
                 "30 readings: zero for 6 hours or more in a row",
                 class = "bayesbem_message_readings_left_out")
  expect_equal(nrow(other), length(time) - 3 - 30)
  expect_output(print(meter_rules()), "over 10 x the median positive reading")
  expect_error(meter_rules(zero_hours = 0), class = "bayesbem_error_argument")
  expect_error(meter_rules(above_median = "10"), class = "bayesbem_error_argument")
})

test_that("a month the meter covers too little is refused, as CalTRACK's sufficiency", {
  truth <- hourly_truth()
  sim <- truth$sim
  time <- as.POSIXct("2013-01-01 00:00", tz = "Etc/GMT+7") + 3600 * (0:(24 * 59 - 1))
  y <- truth$use[hour_of(sim, time)]
  y[24 * 40 + 1:(24 * 5)] <- NA            # five days of February missing: 82 % present
  expect_error(suppressMessages(field_hours(sim, time, y)), "2013-02: 82 %",
               class = "bayesbem_error_sufficiency")
  field <- suppressMessages(field_hours(sim, time, y, sufficiency = 0.8))
  expect_equal(attr(field, "sufficiency"),
               data.frame(month = c("2013-01", "2013-02"), hours = c(744, 672),
                          present = c(744, 672 - 120), share = c(1, 552 / 672)))
  expect_equal(data_sufficiency(field$time), attr(field, "sufficiency"))
  expect_error(data_sufficiency("2013-01-01"), class = "bayesbem_error_argument")
})

test_that("hours of meter data calibrate, the truth inside the posterior", {
  skip_on_cran()
  truth <- hourly_truth()
  sim <- truth$sim
  # two days of hourly readings with noise, stamped at their start
  time <- as.POSIXct("2013-02-04 00:00", tz = "Etc/GMT+7") + 3600 * (0:47)
  y <- truth$use[hour_of(sim, time)] + withr::with_seed(test_seed(1), stats::rnorm(48, 0, 0.05))
  field <- field_hours(sim, time, y)
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% c("equipment_power_density", "infiltration_per_exterior_area"), ]
  hours <- hour_of(sim, field$time)
  runs <- simulate_design(sim, design_lhs(pars, 12, seed = 1))
  runs <- runs[rep(seq_len(nrow(sim$x)), 12) %in% hours, ]
  fit <- suppressWarnings(calibrate(field, runs, chains = 2, iter = 600, seed = test_seed(2)),
                          classes = "bayesbem_warning_convergence")
  expect_equal(fit$data$names$period, "time")
  draws <- posterior::as_draws_matrix(fit)
  for (name in c("equipment_power_density", "infiltration_per_exterior_area")) {
    z <- (mean(draws[, name]) - c(equipment_power_density = 15,
                                  infiltration_per_exterior_area = 8e-4)[[name]]) /
      stats::sd(draws[, name])
    expect_lt(abs(z), 4, label = name)
  }
})

test_that("calendar covariates: hour, weekend and holidays of each period", {
  epw <- shipped_epw(2013)
  christmas <- as.Date("2013-12-25")
  hours <- calendar_covariates(bem_simulator(epw, by = "hour"), holidays = christmas)
  expect_equal(nrow(hours), 8760)
  expect_equal(hours$hour[1:25], c(0:23, 0))
  # 5 January 2013 was a Saturday; Christmas's 24 hours are the holiday's
  expect_equal(hours$weekend[24 * 4 + 1], 1)
  expect_equal(hours$weekend[24 * 3 + 1], 0)
  expect_equal(sum(hours$holiday), 24)
  months <- calendar_covariates(bem_simulator(epw), holidays = christmas)
  # January 2013 held 8 weekend days of 31
  expect_equal(months$weekend[1], 8 / 31)
  expect_equal(months$holiday, c(rep(0, 11), 1 / 31))
  bills <- data.frame(start = as.Date("2013-01-05"), end = as.Date("2013-01-11"))
  expect_equal(calendar_covariates(bem_simulator(epw, periods = bills))$weekend, 2 / 7)
  lin <- simulator(function(params, x) x$a * params$k, data.frame(a = 1:3),
                   data.frame(parameter = "k", initial = 1, min = 0, max = 2))
  expect_error(calendar_covariates(lin), class = "bayesbem_error_argument")
  expect_error(calendar_covariates(bem_simulator(epw), holidays = "2013-12-25"),
               class = "bayesbem_error_argument")
})

test_that("the occupancy estimated from a meter has its weekday and weekend shape", {
  time <- as.POSIXct("2013-06-03", tz = "Europe/London") + 3600 * (0:(24 * 21 - 1))
  hour <- as.integer(format(time, "%H"))
  open <- as.integer(format(time, "%u")) <= 5 & hour >= 8 & hour < 18
  y <- 10 + 30 * open + withr::with_seed(1, stats::rnorm(length(time), 0, 0.1))
  occupancy <- meter_occupancy(time, y)
  expected <- rep(c(rep(c(rep(0, 8), rep(1, 10), rep(0, 6)), 5), rep(0, 48)))
  expect_equal(occupancy, expected, tolerance = 0.02)
  expect_equal(range(occupancy), c(0, 1))
  # in the building's clock: the same readings seen in UTC start an hour earlier
  utc <- meter_occupancy(as.POSIXct(format(time, tz = "UTC"), tz = "UTC"), y)
  expect_equal(utc[8], 1, tolerance = 0.02)
  expect_no_error(bem_building(occupancy = occupancy))
  expect_error(meter_occupancy(time[1:100], y[1:100]), "miss", class = "bayesbem_error_argument")
})

test_that("the loads' share and the heating timer from a meter reproduce its profile", {
  time <- as.POSIXct("2013-01-07", tz = "Europe/London") + 3600 * (0:(24 * 14 - 1))
  hour <- as.integer(format(time, "%H"))
  open <- as.integer(format(time, "%u")) <= 5 & hour >= 8 & hour < 18
  y <- 10 + 30 * open
  # 50 open hours at 40 and 118 others at 10, over the busiest hour's 40
  fraction <- meter_load_fraction(time, y)
  expect_equal(fraction, (50 * 40 + 118 * 10) / 168 / 40)
  # the model's lights' and equipment's profile is then the meter's, base load included
  week <- as.vector(tapply(y, bayesbem:::hour_of_week(time, "Europe/London"), mean))
  expect_equal(bayesbem:::schedule_shape(meter_occupancy(time, y), fraction), week / mean(week))
  expected <- rep(c(rep(c(rep(0, 8), rep(1, 10), rep(0, 6)), 5), rep(0, 48)))
  expect_equal(meter_heating_schedule(time, y), expected)
  expect_equal(meter_heating_schedule(time, y, on = 0.5), expected)
  expect_no_error(bem_building(heating_schedule = meter_heating_schedule(time, y),
                               lighting_fraction = fraction, equipment_fraction = fraction))
  expect_error(meter_heating_schedule(time, y, on = 1), class = "bayesbem_error_argument")
  expect_error(meter_load_fraction(time, 0 * y), class = "bayesbem_error_argument")
  expect_error(meter_load_fraction(time[1:10], y[1:10]), "miss",
               class = "bayesbem_error_argument")
})
