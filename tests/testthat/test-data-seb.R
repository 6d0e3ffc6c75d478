test_that("the shipped case-study data have the documented layout", {
  expect_equal(dim(seb_field), c(12, 5))
  expect_named(seb_field, c("y", "temp", "rh", "solar", "month"))
  expect_equal(seb_field$month, seq(as.Date("2013-01-01"), by = "month", length.out = 12))
  expect_equal(dim(seb_sim), c(120, 7))
  expect_named(seb_sim, c("eta", "temp", "rh", "solar", "fan_total_efficiency",
                          "equipment_power_density", "infiltration_per_exterior_area"))
  # each of the 10 settings repeats the 12 field months
  expect_equal(seb_sim$temp, rep(seb_field$temp, 10), tolerance = 1e-6)
  expect_equal(nrow(unique(seb_sim[5:7])), 10)
})

test_that("seb_holdout holds the 2012 bills with the monthly means of the 2012 weather", {
  expect_named(seb_holdout, c("y", "temp", "rh", "solar", "month", "bill_start", "bill_end"))
  expect_equal(seb_holdout$y, c(1031, 1494, 1428, 1375, 1584, 1934))
  expect_equal(seb_holdout$month, seq(as.Date("2012-01-01"), by = "month", length.out = 6))
  expect_true(all(seb_holdout$bill_start == seb_holdout$month))
  expect_equal(format(seb_holdout$bill_end[1:2]), c("2012-01-30", "2012-02-28"))
  # hourly means of the file's records, computed here independently
  epw <- utils::read.csv(system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem"),
                         skip = 8, header = FALSE)
  month <- epw[[2]]
  keep <- month <= 6
  expect_equal(seb_holdout$temp, as.vector(tapply(epw[[7]][keep], month[keep], mean)))
  expect_equal(seb_holdout$rh, as.vector(tapply(epw[[9]][keep], month[keep], mean)))
  expect_equal(seb_holdout$solar, as.vector(tapply(epw[[15]][keep], month[keep], mean)))
})

test_that("seb_fit is a usable bayesbem_fit of the shipped data", {
  expect_s3_class(seb_fit, "bayesbem_fit")
  expect_equal(seb_fit$data$field, seb_field)
  expect_equal(posterior::ndraws(posterior::as_draws(seb_fit)), 400)
  withr::local_seed(1)
  p <- predict(seb_fit, ndraws = 20)
  expect_equal(nrow(p), 12)
  expect_true(all(is.finite(p$mean)))
})
