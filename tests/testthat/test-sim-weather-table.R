# The shipped 2013 weather of Golden, Colorado (measured at NREL's SRRL) as
# a station would give it: UTC stamps at each hour's end, global radiation.
golden <- list(latitude = 39.74, longitude = -105.18, elevation = 1829, time_zone = -7)

station_table <- function(year = 2013) {
  hourly <- epw_weather(shipped_epw(year), by = "hour")
  time <- hourly$time + 3600
  attr(time, "tzone") <- "UTC"
  list(hourly = hourly,
       station = data.frame(ob_time = time, air_temperature = hourly$temp, rh = hourly$rh,
                            glbl_irad = hourly$ghi))
}

read_golden <- function(station, ...) {
  read_weather(station, latitude = golden$latitude, longitude = golden$longitude,
               elevation = golden$elevation, time_zone = golden$time_zone,
               columns = c(time = "ob_time", temp = "air_temperature", ghi = "glbl_irad"), ...)
}

test_that("the sun's position closes the measured radiation balance, at the hour's middle", {
  # measured global = direct normal x cos(zenith) + diffuse, hour by hour
  # (an independent check of the zenith: half an hour off, it fails)
  for (year in c(2012, 2013)) {
    hourly <- epw_weather(shipped_epw(year), by = "hour")
    closure <- function(shift) {
      sun <- bayesbem:::solar_geometry(hourly$time + shift, golden$latitude, golden$longitude,
                                       golden$time_zone)
      day <- sun$cos_zenith > 0.1
      sum(abs(hourly$dni * sun$cos_zenith + hourly$dhi - hourly$ghi)[day]) / sum(hourly$ghi[day])
    }
    expect_lt(closure(0), 0.03)
    expect_gt(closure(-1800), 2 * closure(0))
    expect_gt(closure(1800), 2 * closure(0))
  }
})

test_that("Erbs's split of the global radiation recovers the measured direct and diffuse", {
  for (year in c(2012, 2013)) {
    data <- station_table(year)
    weather <- read_golden(data$station)
    measured <- data$hourly
    expect_equal(as.numeric(weather$time), as.numeric(measured$time))
    # the global radiation splits exactly into its parts
    sun <- bayesbem:::solar_geometry(weather$time, golden$latitude, golden$longitude,
                                     golden$time_zone)
    expect_equal(weather$dni * pmax(sun$cos_zenith, sin(5 * pi / 180)) + weather$dhi,
                 weather$ghi)
    # hourly, monthly and annual agreement with the measured parts: stated tolerances
    expect_gt(stats::cor(weather$dni, measured$dni), 0.95)
    expect_gt(stats::cor(weather$dhi, measured$dhi), 0.9)
    for (part in c("dni", "dhi")) {
      monthly <- tapply(weather[[part]], measured$month, sum) / tapply(measured[[part]], measured$month, sum)
      expect_lt(max(abs(monthly - 1)), 0.25)
      expect_lt(abs(sum(weather[[part]]) / sum(measured[[part]]) - 1), 0.03)
    }
  }
})

test_that("an EPW written from a station's table reads back hour for hour", {
  data <- station_table()
  weather <- read_golden(data$station, name = "Golden")
  expect_output(print(weather), "Hourly weather of Golden .* 8760 hours \\(8760 measured")
  path <- write_epw(weather, withr::local_tempfile(fileext = ".epw"))
  back <- epw_weather(path, by = "hour")
  expect_identical(as.numeric(back$time), as.numeric(data$hourly$time))
  expect_equal(back$temp, data$hourly$temp)
  expect_equal(back$rh, data$hourly$rh)
  expect_equal(back$ghi, data$hourly$ghi)
  expect_equal(back$dni, round(weather$dni))
  expect_equal(back$weekday, data$hourly$weekday)
  expect_equal(epw_monthly(path)$temp, epw_monthly(shipped_epw(2013))$temp)
})

test_that("a calendar year is kept of a station's hours stamped at their end", {
  station <- station_table()$station
  # a file of a year's stamps: its first reading is the year before's last hour
  shifted <- station
  shifted$ob_time <- shifted$ob_time - 3600
  year <- as.Date(c("2013-01-01", "2013-12-31"))
  expect_error(suppressMessages(read_golden(shifted, days = year)), "missing for 1 hour",
               class = "bayesbem_error_weather")
  weather <- read_golden(shifted, days = as.Date(c("2013-01-01", "2013-12-30")))
  expect_equal(nrow(weather), 364 * 24)
  expect_equal(format(weather$time[1], "%Y-%m-%d %H:%M"), "2013-01-01 00:00")
  expect_equal(weather$temp, station$air_temperature[-1][1:(364 * 24)])
  expect_error(read_golden(station, days = year[2:1]), class = "bayesbem_error_argument")
})

test_that("sub-hourly readings in local time average into the hours of standard time", {
  data <- station_table()
  # 15-minute readings stamped at their start in Denver's clock (summer time)
  hourly <- data$hourly[data$hourly$month == 7, ]
  start <- rep(hourly$time, each = 4) + 900 * (0:3)
  attr(start, "tzone") <- "America/Denver"
  quarter <- data.frame(time = start, temp = rep(hourly$temp, each = 4) + c(-0.3, -0.1, 0.1, 0.3),
                        dew_point = bayesbem:::dew_point(rep(hourly$temp, each = 4), rep(hourly$rh, each = 4)),
                        ghi = rep(hourly$ghi, each = 4), dni = rep(hourly$dni, each = 4),
                        dhi = rep(hourly$dhi, each = 4))
  weather <- read_weather(quarter, latitude = golden$latitude, longitude = golden$longitude,
                          elevation = golden$elevation, time_zone = golden$time_zone,
                          stamps = "start")
  expect_equal(as.numeric(weather$time), as.numeric(hourly$time))
  expect_equal(weather$temp, hourly$temp)
  # the dew point converts back to the relative humidity; given parts are kept
  expect_equal(weather$rh, hourly$rh, tolerance = 1e-6)
  expect_equal(weather$dni, hourly$dni)
})

test_that("short gaps are interpolated and said, long ones refused with their hours", {
  station <- station_table()$station[1:(24 * 14), ]
  station$flagged <- FALSE
  station$flagged[30:31] <- TRUE
  short <- station[-(100:102), ]
  expect_message(weather <- read_golden(short), "3 were interpolated over gaps and 2 were flagged",
                 class = "bayesbem_message_weather_filled")
  expect_equal(sum(weather$filled == "interpolated"), 3)
  expect_equal(weather$temp[100:102],
               stats::approx(c(99, 103), station$air_temperature[c(99, 103)], 100:102)$y)
  long <- station
  long$air_temperature[200:207] <- NA
  expect_snapshot(read_golden(long), error = TRUE)
  expect_error(read_golden(long, max_gap = 8L), NA)
  expect_error(read_golden(station[-2]), "air_temperature|temp", class = "bayesbem_error_columns")
  text <- station
  text$ob_time <- format(text$ob_time, "%Y-%m-%d %H:%M", tz = "UTC")
  expect_equal(as.numeric(read_golden(text)$time), as.numeric(read_golden(station)$time))
  text$ob_time[5] <- "yesterday"
  expect_error(read_golden(text), "Row 5", class = "bayesbem_error_weather")
  expect_error(read_weather(station, latitude = 100, longitude = 0, elevation = 0, time_zone = 0),
               "must be a number from -90 to 90", class = "bayesbem_error_argument")
})

test_that("EnergyPlus runs on an EPW written from a station's table", {
  skip_if_no_eplus()
  path <- write_epw(read_golden(station_table()$station),
                    file.path(withr::local_tempdir(), "golden.epw"))
  written <- simulate_design(eplus_simulator(weather = path), data.frame(fan_total_efficiency = 0.6))
  original <- simulate_design(seb_eplus(), data.frame(fan_total_efficiency = 0.6))
  # the same building on the station's weather: direct and diffuse split
  # from the global, EnergyPlus's own wind and sky defaults
  expect_equal(nrow(written), 12)
  expect_lt(abs(sum(written$eta) / sum(original$eta) - 1), 0.1)
})
