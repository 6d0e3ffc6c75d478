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
  w <- epw_monthly(write_epw(shipped_epw(2013), records))
  expect_equal(w$hours[2], 29 * 24)
  expect_equal(w$days[2], 29)
  hourly <- bayesbem:::read_epw_hourly(write_epw(shipped_epw(2013), records))
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
