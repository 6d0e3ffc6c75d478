test_that("cvrmse() and nmbe() follow ASHRAE Guideline 14", {
  obs <- c(100, 110, 120, 130)
  pred <- c(102, 107, 121, 134)
  # by hand: obs - pred = -2, 3, -1, -4; n - 1 = 3; mean(obs) = 115
  expect_equal(cvrmse(obs, pred), 100 * sqrt((4 + 9 + 1 + 16) / 3) / 115)
  expect_equal(nmbe(obs, pred), 100 * -4 / (3 * 115))
  # n - p degrees of freedom
  expect_equal(cvrmse(obs, pred, p = 2), 100 * sqrt(30 / 2) / 115)
  expect_equal(nmbe(obs, pred, p = 0), 100 * -4 / (4 * 115))
  # the Guideline's sign: a model that predicts too much has a negative NMBE
  expect_lt(nmbe(obs, obs * 1.1), 0)
  expect_equal(cvrmse(obs, obs), 0)
  expect_error(cvrmse(obs, pred[1:3]), class = "bayesbem_error_argument")
  expect_error(nmbe(obs, pred, p = 4), class = "bayesbem_error_argument")
  expect_snapshot(nmbe(1, 1), error = TRUE)
  expect_snapshot(cvrmse(obs, pred, p = "1"), error = TRUE)
})

test_that("calibration_metrics() gives training and held-out metrics with a verdict", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(4)
  held <- seb_field[c(2, 7), ]
  m <- calibration_metrics(fit, newdata = held[2:4], obs = held$y * 1.3, ndraws = 200)
  expect_equal(m$set, rep(c("training", "held-out"), each = 2))
  expect_equal(m$prediction, rep(c("simulator", "calibrated"), 2))
  expect_equal(m$route, rep("emulator", 4))
  expect_equal(m$n, c(12, 12, 2, 2))
  cal <- m[m$prediction == "calibrated", ]
  expect_lt(cal$cvrmse[1], 15)
  expect_lt(abs(cal$nmbe[1]), 5)
  expect_true(cal$calibrated[1])
  # outputs 30 % above the model's predictions fail the monthly limits
  expect_gt(cal$nmbe[2], 5)
  expect_false(cal$calibrated[2])
  # the simulator part alone, by hand from the same draws
  withr::local_seed(4)
  draws <- predict_draws(fit, seb_field[c("temp", "rh", "solar")], ndraws = 200)
  withr::local_seed(4)
  again <- calibration_metrics(fit, ndraws = 200)
  expect_equal(again$cvrmse[1], cvrmse(seb_field$y, colMeans(draws$eta)))
  expect_equal(again$nmbe[2], nmbe(seb_field$y, colMeans(draws$y)))
  hourly <- calibration_metrics(fit, by = "hour", ndraws = 50)
  expect_true(hourly$calibrated[2])
  daily <- calibration_metrics(fit, by = "day", ndraws = 50)
  expect_equal(daily$calibrated, hourly$calibrated)
  expect_snapshot(calibration_metrics(fit, newdata = held[2:4]), error = TRUE)
})

test_that("calibration metrics print with 2 decimals", {
  m <- calibration_metrics(seb_fit, ndraws = 50)
  expect_s3_class(m, "bayesbem_metrics")
  out <- capture.output(print(m))
  expect_match(out[3], sprintf("training +calibrated +emulator 12 +%.2f +%.2f +TRUE",
                               m$cvrmse[2], m$nmbe[2]))
})

test_that("held-out periods predicted through a simulator are labelled so", {
  sim <- linear_seb_simulator()
  withr::local_seed(6)
  m <- calibration_metrics(seb_fit, newdata = sim, obs = seb_field$y * 1.02, ndraws = 10)
  expect_equal(m$route, c("emulator", "emulator", "simulator", "simulator"))
  withr::local_seed(6)
  tr <- calibration_metrics(seb_fit, simulator = sim, ndraws = 10)
  expect_equal(tr$route, c("simulator", "simulator"))
  p <- withr::with_seed(6, predict_scenario(seb_fit, sim, ndraws = 10, noise = FALSE))
  expect_equal(tr$cvrmse[1], cvrmse(seb_field$y, colMeans(p$simulated)))
  expect_error(calibration_metrics(seb_fit, newdata = sim, obs = 1:3),
               class = "bayesbem_error_argument")
})

test_that("held-out periods without a measurement are left out", {
  sim <- linear_seb_simulator()
  obs <- c(seb_field$y[1:6] * 1.02, rep(NA, 6))
  withr::local_seed(6)
  m <- calibration_metrics(seb_fit, newdata = sim, obs = obs, ndraws = 10)
  # the same random numbers: the training rows' draws come first
  withr::local_seed(6)
  invisible(predict_draws(seb_fit, seb_field[c("temp", "rh", "solar")], ndraws = 10))
  p <- predict_scenario(seb_fit, sim, ndraws = 10, noise = FALSE)
  expect_equal(m$n[3:4], c(6, 6))
  expect_equal(m$cvrmse[4], cvrmse(obs[1:6], colMeans(p$y)[1:6]))
  expect_equal(m$nmbe[3], nmbe(obs[1:6], colMeans(p$simulated)[1:6]))
  # the emulator route, on the rows with a measurement
  extrapolates <- "bayesbem_warning_extrapolation"
  withr::local_seed(7)
  expect_warning(em <- calibration_metrics(seb_fit, newdata = seb_holdout,
                                           obs = c(NA, seb_holdout$y[-1]), ndraws = 50),
                 class = extrapolates)
  withr::local_seed(7)
  expect_warning(again <- calibration_metrics(seb_fit, newdata = seb_holdout[-1, ],
                                              obs = seb_holdout$y[-1], ndraws = 50),
                 class = extrapolates)
  expect_equal(em, again)
  expect_error(calibration_metrics(seb_fit, newdata = sim, obs = rep(NA_real_, 12)),
               class = "bayesbem_error_argument")
})

test_that("a fit on several outputs gets each output's metrics, with a column output", {
  skip_on_cran()
  both <- on_both_outputs(calibration_metrics, 4, ndraws = 20)
  expect_s3_class(both$all, "bayesbem_metrics")
  expect_equal(both$all$cvrmse[both$electricity], both$own$cvrmse)
  expect_output(print(both$all), "gas")
  expect_error(calibration_metrics(both$fit, newdata = seb_field, obs = seb_field$y),
               class = "bayesbem_error_argument")
})

test_that("the calibrated simulator and the TOWT baseline are scored on the same held-out hours", {
  skip_on_cran()
  sim <- bem_simulator(shipped_epw(2013), by = "hour")
  truth <- list(equipment_power_density = 15, infiltration_per_exterior_area = 8e-4)
  use <- simulate_design(sim, as.data.frame(truth))$eta
  noisy <- use + withr::with_seed(test_seed(4), stats::rnorm(length(use), 0, 0.05))
  hours <- sim$periods$start
  # train on two weeks of January (TOWT needs more than one of each hour of
  # the week), hold out two weeks over the month's end
  train <- which(hours >= as.POSIXct("2013-01-07", tz = "Etc/GMT+7"))[1] + 0:335
  held <- which(hours >= as.POSIXct("2013-01-25", tz = "Etc/GMT+7"))[1] + 0:335
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% names(truth), ]
  runs <- simulate_design(sim, design_lhs(pars, 12, seed = 1))
  runs <- runs[rep(seq_along(hours), 12) %in% train, ]
  field <- data.frame(y = noisy[train], sim$x[train, ], time = hours[train])
  # (the additive discrepancy predicts a year of hours at a cost linear in them)
  fit <- suppressWarnings(calibrate(field, runs, chains = 2, iter = 1000, warmup = 500,
                                    seed = test_seed(5), discrepancy_kernel = "additive",
                                    progress = FALSE))
  baseline <- towt_baseline(field)
  obs <- rep(NA_real_, length(hours))
  obs[held] <- noisy[held]
  cache <- withr::local_tempdir()
  table <- withr::with_seed(6, compare_baseline(fit, baseline, sim, obs, ndraws = 20, cache_dir = cache))
  expect_s3_class(table, "bayesbem_metrics")
  expect_equal(table$prediction, c("calibrated", "baseline", "calibrated", "baseline"))
  expect_equal(table$by, c("hour", "hour", "month", "month"))
  expect_equal(table$n, c(336, 336, 2, 2))
  # the same draws by hand: the simulator at 20 draws with its noise
  draws <- withr::with_seed(6, predict_scenario(fit, sim, ndraws = 20, cache_dir = cache))$y[, held]
  expect_equal(table$cvrmse[1], cvrmse(noisy[held], colMeans(draws)))
  month <- format(hours[held], "%m")
  totals <- sapply(c("01", "02"), function(m) rowSums(draws[, month == m]))
  expect_equal(table$nmbe[3], nmbe(tapply(noisy[held], month, sum), colMeans(totals)))
  rows <- predict(baseline, data.frame(temp = sim$x$temp[held], time = hours[held]))
  expect_equal(table$cvrmse[2], cvrmse(noisy[held], rows$mean))
  expect_equal(table$coverage[2], mean(noisy[held] >= rows$q5 & noisy[held] <= rows$q95))
  # the simulator at the truth's neighbourhood covers most held-out hours,
  # and so does the baseline's t interval
  expect_gt(table$coverage[1], 0.7)
  expect_gt(table$coverage[2], 0.7)
  expect_error(compare_baseline(fit, fit, sim, obs), class = "bayesbem_error_argument")
})
