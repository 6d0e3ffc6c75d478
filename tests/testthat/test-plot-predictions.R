test_that("plot_predictions_data() has one row per point and input", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(1)
  d <- plot_predictions_data(fit, ndraws = 100)
  expect_equal(nrow(d), 36)
  expect_equal(levels(d$input), c("temp", "rh", "solar"))
  expect_equal(d$x[d$input == "rh"], seb_field$rh)
  expect_equal(d$obs[d$input == "temp"], seb_field$y)
  expect_true(all(d$q5 <= d$q25 & d$q25 <= d$q50 & d$q50 <= d$q75 & d$q75 <= d$q95))
})

test_that("plot_components_data() gives eta + delta, eta and delta / y per set", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(1)
  d <- plot_components_data(fit, newdata = seb_field[1:2, 2:4], obs = seb_field$y[1:2],
                            ndraws = 100)
  expect_equal(levels(d$set), c("training", "held-out"))
  expect_equal(levels(d$component), c("eta + delta", "eta", "delta / y (%)"))
  expect_equal(nrow(d), 3 * (12 + 2))
  share <- d[d$component == "delta / y (%)", ]
  expect_true(all(is.na(share$obs)))
  expect_true(all(abs(share$q50) < 25))
  expect_error(plot_components_data(fit, newdata = seb_field[1:2, 2:4]),
               class = "bayesbem_error_argument")
})

test_that("plot_components_data() labels the periods and matches predict()", {
  withr::local_seed(2)
  d <- plot_components_data(seb_fit, newdata = seb_field[1:2, ], obs = seb_field$y[1:2],
                            ndraws = 60)
  training <- d[d$set == "training" & d$component == "eta + delta", ]
  expect_equal(as.character(training$period), paste(month.abb, 2013))
  held <- d[d$set == "held-out" & d$component == "eta", ]
  expect_equal(as.character(held$period), c("Jan 2013", "Feb 2013"))
  # the medians are those of predict()'s draws for the same seed
  withr::local_seed(2)
  y <- predict(seb_fit, ndraws = 60, summary = FALSE)
  expect_equal(training$q50, apply(y, 2, median), tolerance = 1e-8)
  # and close to the data the fit was calibrated on
  expect_lt(max(abs(training$q50 - seb_field$y) / seb_field$y), 0.1)
  unlabelled <- plot_components_data(seb_fit, newdata = seb_field[1:2, 2:4],
                                     obs = seb_field$y[1:2], ndraws = 20)
  expect_equal(as.character(unique(unlabelled$period[unlabelled$set == "held-out"])),
               c("1", "2"))
})

# drawn from the shipped seb_fit with a fixed seed: the same on every machine
test_that("prediction plots draw", {
  skip_if_not_installed("vdiffr")
  withr::local_seed(1)
  vdiffr::expect_doppelganger("predictions", plot_predictions(seb_fit, ndraws = 100))
  withr::local_seed(1)
  vdiffr::expect_doppelganger(
    "components",
    plot_components(seb_fit, newdata = seb_field[1:3, ], obs = seb_field$y[1:3], ndraws = 100)
  )
})

test_that("plots of a fit on several outputs have a row of panels per output", {
  skip_on_cran()
  fit <- two_output_fit()
  d <- plot_components_data(fit, ndraws = 20)
  expect_equal(levels(d$output), c("electricity", "gas"))
  # each output at its own field periods: gas has one bill fewer
  expect_equal(as.vector(table(d$output[d$component == levels(d$component)[1]])), c(12L, 11L))
  gas <- plot_components_data(output_fit(fit, "gas"), ndraws = 20)
  expect_equal(d[d$output == "gas", "obs"], gas$obs)
  expect_s3_class(plot_components(fit, ndraws = 20), "ggplot")
  p <- plot_predictions_data(fit, ndraws = 20)
  expect_equal(nrow(p), 3 * (12 + 11))
  expect_s3_class(plot_predictions(fit, ndraws = 20), "ggplot")
  expect_error(plot_predictions(fit, newdata = seb_field), class = "bayesbem_error_argument")
  expect_equal(levels(plot_posteriors_data(fit)$parameter), fit$data$names$t)
  expect_setequal(unique(plot_trace_data(fit, c("gas:lambda_e", "equipment_power_density"))$parameter),
                  c("gas:lambda_e", "equipment_power_density"))
})
