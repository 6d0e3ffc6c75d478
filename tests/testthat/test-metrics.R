test_that("cvrmse() and nmbe() follow ASHRAE Guideline 14", {
  obs <- c(100, 110, 120, 130)
  pred <- c(102, 107, 121, 134)
  # by hand: errors 2, -3, 1, 4; n - 1 = 3; mean(obs) = 115
  expect_equal(cvrmse(obs, pred), 100 * sqrt((4 + 9 + 1 + 16) / 3) / 115)
  expect_equal(nmbe(obs, pred), 100 * 4 / (3 * 115))
  expect_equal(cvrmse(obs, obs), 0)
  expect_error(cvrmse(obs, pred[1:3]), class = "bayesbem_error_argument")
  expect_snapshot(nmbe(1, 1), error = TRUE)
})

test_that("calibration_metrics() gives training and held-out metrics with a verdict", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(4)
  held <- seb_field[c(2, 7), ]
  m <- calibration_metrics(fit, newdata = held[2:4], obs = held$y * 1.3, ndraws = 200)
  expect_equal(m$set, c("training", "held-out"))
  expect_equal(m$n, c(12, 2))
  expect_lt(m$cvrmse[1], 15)
  expect_lt(abs(m$nmbe[1]), 5)
  expect_true(m$calibrated[1])
  # outputs 30 % above the model's predictions fail the monthly limits
  expect_lt(m$nmbe[2], -5)
  expect_false(m$calibrated[2])
  hourly <- calibration_metrics(fit, frequency = "hourly", ndraws = 50)
  expect_true(hourly$calibrated)
  expect_snapshot(calibration_metrics(fit, newdata = held[2:4]), error = TRUE)
})

test_that("calibration metrics print with 2 decimals", {
  m <- calibration_metrics(seb_fit, ndraws = 50)
  expect_s3_class(m, "koh_metrics")
  out <- capture.output(print(m))
  expect_match(out[2], sprintf("training 12 +%.2f +%.2f +TRUE", m$cvrmse, m$nmbe))
})
