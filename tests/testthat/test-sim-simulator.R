linear_simulator <- function(fun = function(params, x) params$a * x$temp + params$b) {
  simulator(fun, x = data.frame(temp = c(0, 10, 20)),
            parameters = data.frame(parameter = c("a", "b"), initial = c(1, 0),
                                    min = c(0, -5), max = c(2, 5)))
}

test_that("any R function can be wrapped as a simulator", {
  sim <- linear_simulator()
  expect_s3_class(sim, "bayesbem_simulator")
  expect_output(print(sim), "3 periods")
  settings <- bayesbem:::design_settings(sim, data.frame(a = 2))
  # parameters a design does not vary stay at their initial values
  expect_equal(settings, list(list(a = 2, b = 0)))
})

test_that("the embedded model is a simulator over monthly weather", {
  sim <- bem_simulator(shipped_epw(2013))
  expect_named(sim$x, c("temp", "rh", "solar"))
  expect_equal(sim$x$temp, seb_field$temp, tolerance = 1e-12)
  expect_equal(nrow(sim$parameters), 14)
  gas <- bem_simulator(shipped_epw(2013), output = "gas")
  expect_match(gas$name, "gas")
})

test_that("bad simulators and parameter tables get classed errors", {
  expect_error(simulator("f", data.frame(a = 1), bem_parameters()), class = "bayesbem_error_argument")
  expect_error(simulator(function(params, x) 1, data.frame(a = 1), data.frame(parameter = "a")),
               class = "bayesbem_error_parameters")
  sim <- linear_simulator()
  expect_snapshot(simulate_design(sim, data.frame(c = 1)), error = TRUE)
  expect_snapshot(simulate_design(sim, data.frame(a = 3)), error = TRUE)
})

test_that("the embedded model gives both meters from one run", {
  both <- two_output_simulator()
  expect_match(both$name, "electricity and gas")
  p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  w <- epw_monthly(shipped_epw(2013))
  expect_equal(both$fun(p, both$x), bem_monthly(p, w)[c("electricity", "gas")])
  expect_snapshot(bem_simulator(shipped_epw(2013), output = c("electricity", "water")),
                  error = TRUE)
  expect_error(bem_simulator(shipped_epw(2013), output = character()),
               class = "bayesbem_error_argument")
  # a part of the table would leave the model without the others' values
  expect_snapshot(bem_simulator(shipped_epw(2013), parameters = bem_parameters()[12:13, ]),
                  error = TRUE)
})

test_that("output_simulator() gives one output of a simulator of several", {
  both <- two_output_simulator()
  gas <- output_simulator(both, "gas")
  design <- data.frame(infiltration_per_exterior_area = c(0.0005, 0.001))
  runs <- simulate_design(both, design)
  expect_equal(simulate_design(gas, design)$eta, runs$eta[runs$output == "gas"])
  expect_match(gas$name, ": gas$")
  water <- output_simulator(both, "water")
  expect_warning(out <- simulate_design(water, design), class = "bayesbem_warning_simulation")
  expect_match(attr(out, "failed")$error[1], "no output \"water\"", fixed = TRUE)
  expect_error(output_simulator("sim", "gas"), class = "bayesbem_error_argument")
})

test_that("simulator() checks its periods as epw_weather() does, naming the rows", {
  fun <- function(params, x) params$a * x$temp
  pars <- data.frame(parameter = "a", initial = 1, min = 0, max = 2)
  x <- data.frame(temp = c(1, 2, 3))
  days <- data.frame(start = as.Date(c("2013-01-01", "2013-02-01", "2013-03-01")),
                     end = as.Date(c("2013-01-31", "2013-02-28", "2013-03-31")))
  expect_equal(simulator(fun, x, pars, periods = days)$periods, days)
  backwards <- days
  backwards$end[2] <- as.Date("2013-01-15")
  expect_error(simulator(fun, x, pars, periods = backwards), "Row 2", class = "bayesbem_error_periods")
  overlapping <- days
  overlapping$start[3] <- as.Date("2013-02-28")
  expect_error(simulator(fun, x, pars, periods = overlapping), "Row 3 of `periods` overlaps",
               class = "bayesbem_error_periods")
  expect_error(simulator(fun, x, pars, periods = days[1:2, ]), "one row per row of `x` \\(3\\)",
               class = "bayesbem_error_periods")
  # hours: each period ends where the next starts
  start <- as.POSIXct("2013-01-01 00:00", tz = "Etc/GMT+7") + 3600 * 0:2
  hours <- data.frame(start = start, end = start + 3600)
  expect_equal(simulator(fun, x, pars, periods = hours)$periods, hours)
  late <- hours
  late$start[3] <- late$start[3] - 1800
  expect_error(simulator(fun, x, pars, periods = late), "Row 3 of `periods` starts before the period above ends",
               class = "bayesbem_error_periods")
  empty <- hours
  empty$end[1] <- empty$start[1]
  expect_error(simulator(fun, x, pars, periods = empty), "Row 1 of `periods` ends no later than it starts",
               class = "bayesbem_error_periods")
  expect_error(simulator(fun, x, pars, periods = hours[c(2, 1, 3), ]), "Row 2 of `periods` starts before the period above",
               class = "bayesbem_error_periods")
})

test_that("an R function receives the days of bills on their own dates", {
  epw <- shipped_epw(2013)
  bills <- data.frame(start = as.Date(c("2013-01-05", "2013-02-04", "2013-03-10")),
                      end = as.Date(c("2013-02-03", "2013-03-05", "2013-04-03")))
  degree_days <- function(params, x, days) {
    as.vector(tapply(pmax(params$base - days$temp, 0), days$period, sum))
  }
  pars <- data.frame(parameter = "base", initial = 15, min = 10, max = 20)
  x <- epw_weather(epw, periods = bills)[c("temp", "days")]
  sim <- simulator(degree_days, x, pars, periods = bills, weather = epw)
  runs <- simulate_design(sim, data.frame(base = c(12, 18)))
  # by hand: each day's mean of its 24 records, from the file's own lines
  records <- utils::read.csv(epw, skip = 8, header = FALSE)
  date <- as.Date(sprintf("%d-%02d-%02d", records$V1, records$V2, records$V3))
  daily <- tapply(records$V7, date, mean)
  for (base in c(12, 18)) {
    expected <- vapply(seq_len(nrow(bills)), function(i) {
      in_bill <- as.Date(names(daily)) >= bills$start[i] & as.Date(names(daily)) <= bills$end[i]
      sum(pmax(base - daily[in_bill], 0))
    }, numeric(1))
    expect_equal(runs$eta[runs$base == base], expected)
  }
  # a period beyond the file, days without periods, a function without days
  late <- bills
  late$end[3] <- as.Date("2014-01-10")
  expect_error(simulator(degree_days, x, pars, periods = late, weather = epw),
               "Period 3", class = "bayesbem_error_periods")
  expect_error(simulator(degree_days, x, pars, weather = epw), class = "bayesbem_error_periods")
  expect_error(simulator(function(params, x) x$temp, x, pars, periods = bills, weather = epw),
               "third argument", class = "bayesbem_error_argument")
})

test_that("the previous day's mean temperature tells apart hours that share their inputs", {
  sim <- bem_simulator(shipped_epw(2013), by = "hour")
  lagged <- with_lagged_temperature(sim)
  temp <- sim$x$temp
  expect_equal(lagged$x$temp_lag[30], mean(temp[6:29]))
  expect_equal(lagged$x$temp_lag[c(1, 2, 3)], c(temp[1], temp[1], mean(temp[1:2])))
  expect_equal(lagged$x[names(sim$x)], sim$x)
  expect_equal(with_lagged_temperature(sim, hours = 3)$x$temp_lag[10], mean(temp[7:9]))
  # hours of equal inputs (calm nights) there are without it, none with it
  shared <- function(x) sum(duplicated(x))
  expect_gt(shared(sim$x), 0)
  expect_equal(shared(lagged$x), 0)
  expect_error(with_lagged_temperature(bem_simulator(shipped_epw(2013))),
               class = "bayesbem_error_argument")
})
