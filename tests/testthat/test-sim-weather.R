test_that("the 2013 weather reproduces the case study's temp and rh exactly", {
  w <- epw_monthly(shipped_epw(2013))
  expect_equal(w$month, 1:12)
  expect_equal(w$temp, seb_field$temp, tolerance = 1e-12)
  expect_equal(w$rh, seb_field$rh, tolerance = 1e-12)
  # the case study's solar input is within 2.5 % of the direct normal radiation
  expect_lt(max(abs(w$dni - seb_field$solar) / seb_field$solar), 0.025)
  expect_equal(sum(w$hours), 8760)
  expect_equal(sum(w$days), 365)
})

test_that("a typical-year file from EnergyPlus reads, with degree-days", {
  tmy <- golden_tmy3()
  skip_if(tmy == "", "the Golden TMY3 file of ../shared/energyplus is not here")
  w <- epw_monthly(tmy)
  expect_equal(nrow(w), 12)
  expect_equal(w$hours, c(31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31) * 24)
  expect_true(all(w$hdd >= 0 & w$cdd >= 0))
  expect_gt(w$hdd[1], w$hdd[7])
  expect_gt(w$cdd[7], w$cdd[1])
  expect_true(all(w$rh > 0 & w$rh < 100))
})

test_that("leap days and missing-value codes are handled", {
  lines <- readLines(shipped_epw(2013))
  records <- lines[-(1:8)]
  feb28 <- grep("^2013,2,28,", records)
  leap <- sub("^2013,2,28,", "2012,2,29,", records[feb28])
  records <- append(records, leap, after = max(feb28))
  # a missing dry-bulb temperature (99.9) and a missing humidity (999)
  first <- strsplit(records[1], ",")[[1]]
  first[7] <- "99.9"
  first[9] <- "999"
  records[1] <- paste(first, collapse = ",")
  w <- epw_monthly(epw_with_records(shipped_epw(2013), records))
  expect_equal(w$hours[2], 29 * 24)
  expect_equal(w$days[2], 29)
  hourly <- bayesbem:::read_epw_hourly(epw_with_records(shipped_epw(2013), records))
  expect_true(is.na(hourly$temp[1]))
  expect_equal(w$temp[1], mean(hourly$temp[hourly$month == 1], na.rm = TRUE))
  expect_false(anyNA(w))
})

test_that("files that are not EPW get classed errors", {
  expect_error(epw_monthly("no-such-file.epw"), class = "bayesbem_error_weather")
  bad <- tempfile(fileext = ".epw")
  writeLines(c("a,b,c", "1,2,3"), bad)
  expect_error(epw_monthly(bad), class = "bayesbem_error_weather")
  expect_snapshot(epw_monthly(bad), error = TRUE, transform = function(x) gsub(bad, "<file>", x, fixed = TRUE))
})

test_that("weather by day and week are the means of their hours, dated", {
  epw <- shipped_epw(2013)
  hourly <- bayesbem:::read_epw_hourly(epw)
  d <- epw_daily(epw)
  expect_equal(nrow(d), 365)
  expect_equal(d$date, seq(as.Date("2013-01-01"), by = "day", length.out = 365))
  expect_equal(unique(d$hours), 24)
  expect_equal(d$temp[40], mean(hourly$temp[hourly$month == 2 & hourly$day == 9]))
  expect_equal(d$hdd[40], max(18.3 - d$temp[40], 0))
  expect_equal(d$cdd[200], max(d$temp[200] - 18.3, 0))
  w <- epw_weather(epw, by = "week")
  expect_equal(nrow(w), 53)
  expect_equal(w$days, c(rep(7, 52), 1))
  expect_equal(w$rh[2], mean(hourly$rh[169:336]))
  expect_equal(w$hdd[2], sum(d$hdd[8:14]))
  # the monthly sums of the daily degree-days are the monthly degree-days
  m <- epw_monthly(epw)
  expect_equal(m$hdd, as.vector(tapply(d$hdd, d$month, sum)))
  expect_equal(m$date, seq(as.Date("2013-01-01"), by = "month", length.out = 12))
  expect_error(epw_weather(epw, by = "year"), class = "bayesbem_error_argument")
  # a daily table drives the embedded model, one output per day
  daily_out <- simulate_design(bem_simulator(d), data.frame(equipment_power_density = 12))$eta
  expect_length(daily_out, 365)
  expect_true(all(daily_out > 0))
})

test_that("weather tables carry the fits' input names, so predict() takes them as they are", {
  w <- epw_monthly(shipped_epw(2013))
  expect_equal(w$solar, w$dni)
  expect_equal(w[c("temp", "rh")], seb_field[c("temp", "rh")], ignore_attr = TRUE)
  # the file's solar radiation reaches 4.6 W/m2 beyond the fit's
  extrapolates <- "bayesbem_warning_extrapolation"
  withr::local_seed(1)
  expect_warning(from_weather <- predict(seb_fit, w, ndraws = 20), "in solar", class = extrapolates)
  withr::local_seed(1)
  expect_warning(by_hand <- predict(seb_fit, data.frame(temp = w$temp, rh = w$rh, solar = w$dni),
                                    ndraws = 20), class = extrapolates)
  expect_equal(from_weather$mean, by_hand$mean)
})
