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

test_that("seb_fit is a usable koh_fit of the shipped data", {
  expect_s3_class(seb_fit, "koh_fit")
  expect_equal(seb_fit$data$field, seb_field)
  expect_equal(posterior::ndraws(posterior::as_draws(seb_fit)), 400)
  withr::local_seed(1)
  p <- predict(seb_fit, ndraws = 20)
  expect_equal(nrow(p), 12)
  expect_true(all(is.finite(p$mean)))
})
