# Bills read on their own days: 30 days from 5 January, 30 from 4
# February, 29 from 6 March, then a missing bill, 28 days from 1 May.
shifted_bills <- function() {
  data.frame(start = as.Date(c("2013-01-05", "2013-02-04", "2013-03-06", "2013-05-01")),
             end = as.Date(c("2013-02-03", "2013-03-05", "2013-04-03", "2013-05-28")))
}

# The hourly records of a weather file on each day from `start` to `end`.
records_between <- function(hourly, start, end) {
  dates <- as.Date(sprintf("%04d-%02d-%02d", hourly$year, hourly$month, hourly$day))
  hourly[dates >= start & dates <= end, ]
}

test_that("a period's weather is the mean of the hours of its days, gaps left out", {
  epw <- shipped_epw(2013)
  bills <- shifted_bills()
  w <- epw_weather(epw, periods = bills)
  hourly <- bayesbem:::read_epw_hourly(epw)
  expect_equal(w$date, bills$start)
  expect_equal(w$end, bills$end)
  expect_equal(w$days, c(30, 30, 29, 28))
  expect_equal(w$hours, 24 * w$days)
  for (i in seq_len(nrow(bills))) {
    h <- records_between(hourly, bills$start[i], bills$end[i])
    expect_equal(w$temp[i], mean(h$temp))
    expect_equal(w$rh[i], mean(h$rh))
    expect_equal(w$solar[i], mean(h$dni))
    expect_equal(w$ghi[i], mean(h$ghi))
  }
  daily <- epw_daily(epw)
  in_first <- daily$date >= bills$start[1] & daily$date <= bills$end[1]
  expect_equal(w$hdd[1], sum(daily$hdd[in_first]))
  # calendar months as periods are the monthly table
  months <- data.frame(start = seq(as.Date("2013-01-01"), by = "month", length.out = 12))
  months$end <- c(months$start[-1] - 1, as.Date("2013-12-31"))
  monthly <- epw_monthly(epw)
  expect_equal(epw_weather(epw, periods = months)[names(monthly)], monthly)
  expect_equal(monthly$end, months$end)
  # dates as strings serve
  as_text <- data.frame(start = format(bills$start), end = format(bills$end))
  expect_equal(epw_weather(epw, periods = as_text), w)
})

test_that("a typical year is matched by month and day, over the year's end too", {
  # a typical-year file: the 2013 records with January from 1999
  records <- readLines(shipped_epw(2013))[-(1:8)]
  records <- sub("^2013,1,", "1999,1,", records)
  tmy <- epw_with_records(shipped_epw(2013), records)
  winter <- data.frame(start = as.Date("2019-12-16"), end = as.Date("2020-01-14"))
  w <- epw_weather(tmy, periods = winter)
  hourly <- bayesbem:::read_epw_hourly(tmy)
  held <- (hourly$month == 12 & hourly$day >= 16) | (hourly$month == 1 & hourly$day <= 14)
  expect_equal(w$days, 30)
  expect_equal(w$temp, mean(hourly$temp[held]))
  expect_equal(w$date, winter$start)
  # the typical year has no 29 February: a leap-year bill holds a day less
  leap <- epw_weather(tmy, periods = data.frame(start = "2020-02-20", end = "2020-03-05"))
  expect_equal(leap$days, 14)
  expect_snapshot(epw_weather(tmy, periods = data.frame(start = c("2019-03-01", "2020-03-10"),
                                                         end = c("2019-03-31", "2020-04-09"))),
                  error = TRUE, transform = function(x) gsub(tmy, "<file>", x, fixed = TRUE))
})

test_that("bad periods are classed errors that name the rows", {
  epw <- shipped_epw(2013)
  bills <- shifted_bills()
  expect_snapshot(error = TRUE, {
    epw_weather(epw, periods = bills[c(2, 1, 3), ])
    epw_weather(epw, periods = transform(bills, end = start - 1))
    epw_weather(epw, periods = rbind(bills[1:2, ], bills[2, ]))
    epw_weather(epw, periods = data.frame(start = c("2013-01-01", "2013-13-01"),
                                          end = c("2013-01-31", "2014-01-31")))
    epw_weather(epw, periods = data.frame(start = "2013-12-01", end = "2014-01-05"))
    epw_weather(epw, periods = data.frame(first = "2013-12-01", last = "2014-01-05"))
    epw_weather(epw, periods = data.frame(start = 1, end = 2))
    epw_weather(epw, by = "month", periods = bills)
  }, transform = function(x) gsub(epw, "<file>", x, fixed = TRUE))
  expect_error(epw_weather(epw, periods = bills[0, ]), class = "bayesbem_error_periods")
  expect_error(epw_weather(epw, periods = transform(bills, end = as.Date(NA))),
               class = "bayesbem_error_periods")
})

test_that("the embedded model runs each period at its weather, days an input when lengths differ", {
  epw <- shipped_epw(2013)
  bills <- shifted_bills()
  sim <- bem_simulator(epw, periods = bills, output = c("electricity", "gas"))
  expect_named(sim$x, c("temp", "rh", "solar", "days"))
  expect_equal(sim$x$days, c(30, 30, 29, 28))
  runs <- simulate_design(sim, data.frame(equipment_power_density = 12))
  p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  p$equipment_power_density <- 12
  truth <- bem_monthly(p, epw_weather(epw, periods = bills))
  expect_equal(runs$eta[runs$output == "gas"], truth$gas)
  # a longer bill at the same weather holds more use: the model is
  # proportional to the hours at a period's mean weather
  w <- epw_weather(epw, periods = bills)[1, ]
  longer <- transform(w, hours = 2 * hours)
  expect_equal(bem_monthly(p, longer)$electricity, 2 * bem_monthly(p, w)$electricity)
  # periods of one length: days is no input (it would be constant)
  weeks <- data.frame(start = as.Date(c("2013-01-07", "2013-01-21")),
                      end = as.Date(c("2013-01-13", "2013-01-27")))
  expect_named(bem_simulator(epw, periods = weeks)$x, c("temp", "rh", "solar"))
  expect_error(bem_simulator(epw_monthly(epw), periods = bills), class = "bayesbem_error_argument")
})

test_that("bills on their own dates calibrate, the truth inside the posterior", {
  skip_on_cran()
  epw <- shipped_epw(2013)
  # twelve bills of 26 to 34 days from 3 January
  lengths <- c(34, 29, 32, 26, 27, 32, 30, 28, 30, 31, 30, 28)
  start <- as.Date("2013-01-03") + c(0, cumsum(lengths)[-12])
  bills <- data.frame(start = start, end = start + lengths - 1)
  sim <- bem_simulator(epw, periods = bills)
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% c("equipment_power_density", "infiltration_per_exterior_area"), ]
  runs <- simulate_design(sim, design_lhs(pars, 15, seed = 1))
  truth <- list(equipment_power_density = 15, infiltration_per_exterior_area = 8e-4)
  field <- simulate_field(sim, truth, noise_sd = 20, seed = test_seed(2))
  field$start <- bills$start
  fit <- suppressWarnings(calibrate(field, runs, chains = 2, iter = 800, seed = test_seed(3)),
                          classes = "bayesbem_warning_convergence")
  expect_equal(fit$data$names$x, c("temp", "rh", "solar", "days"))
  expect_equal(fit$data$names$period, "start")
  draws <- posterior::as_draws_matrix(fit)
  for (name in names(truth)) {
    z <- (mean(draws[, name]) - truth[[name]]) / stats::sd(draws[, name])
    expect_lt(abs(z), 4, label = name)
  }
})

test_that("two meters read on other days: every meter over all periods, each output its own", {
  skip_on_cran()
  epw <- shipped_epw(2013)
  elec <- data.frame(start = as.Date("2013-01-05") + 30 * (0:5))
  elec$end <- elec$start + 29
  gas <- data.frame(start = as.Date("2013-01-15") + 30 * (0:5))
  gas$end <- gas$start + 29
  sim <- bem_simulator(epw, output = c("electricity", "gas"),
                       periods = list(electricity = elec, gas = gas))
  expect_equal(nrow(sim$x), 12)
  expect_equal(sim$periods$start, sort(c(elec$start, gas$start)))
  # the weather of each period is its own table's
  own <- epw_weather(epw, periods = gas)
  at <- match(gas$start, sim$periods$start)
  expect_equal(sim$x$temp[at], own$temp)
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% c("equipment_power_density", "infiltration_per_exterior_area"), ]
  runs <- simulate_design(sim, design_lhs(pars, 12, seed = 1))
  truth <- list(equipment_power_density = 15, infiltration_per_exterior_area = 8e-4)
  field <- simulate_field(sim, truth, noise_sd = c(electricity = 20, gas = 20), seed = test_seed(2))
  period <- rep(seq_len(12), 2)
  mine <- (field$output == "electricity" & period %in% match(elec$start, sim$periods$start)) |
    (field$output == "gas" & period %in% at)
  fit <- suppressWarnings(calibrate(field[mine, ], runs, chains = 2, iter = 600, seed = test_seed(3)),
                          classes = "bayesbem_warning_convergence")
  expect_equal(vapply(fit$data$outputs, `[[`, integer(1), "n"), c(electricity = 6L, gas = 6L))
  # a tool that reruns the simulator finds each output's periods in it
  checks <- validate_emulator(fit, sim, ndraws = 2)
  expect_equal(nrow(checks$gas$table), 2 * 6)
  expect_error(bem_simulator(epw, output = c("electricity", "gas"), periods = list(gas = gas)),
               class = "bayesbem_error_periods")
})
