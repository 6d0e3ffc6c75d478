test_that("plot() dispatches to each plot type", {
  skip_on_cran()
  fit <- shared_fit()
  expect_s3_class(plot(fit), "ggplot")
  expect_identical(plot(fit)$labels$y, "density")
  expect_s3_class(plot(fit, type = "trace"), "ggplot")
  expect_s3_class(plot(fit, type = "predictions", ndraws = 20), "ggplot")
  expect_s3_class(plot(fit, type = "components", ndraws = 20), "ggplot")
  expect_error(plot(fit, type = "pairs"))
})

test_that("plot functions take the object as x; the old argument names still work", {
  withr::local_options(lifecycle_verbosity = "warning")
  expect_warning(old <- plot_posteriors_data(fit = seb_fit), class = "lifecycle_warning_deprecated")
  expect_equal(old, plot_posteriors_data(seb_fit))
  expect_warning(plot_trace_data(fit = seb_fit), class = "lifecycle_warning_deprecated")
  withr::local_seed(1)
  expect_warning(old <- plot_predictions_data(fit = seb_fit, ndraws = 20),
                 class = "lifecycle_warning_deprecated")
  withr::local_seed(1)
  expect_equal(old, plot_predictions_data(x = seb_fit, ndraws = 20))
  expect_error(plot_posteriors_data(), class = "error")
})

test_that("plot() of a result draws what its plot_*() draws", {
  d <- discrepancy(seb_fit, ndraws = 50)
  expect_identical(plot(d)$data, plot_discrepancy(d)$data)
  id <- identifiability(seb_fit, ndraws = 20)
  expect_identical(plot(id)$data, plot_identifiability(id)$data)
  expect_error(plot(d, colour = "red"), class = "rlib_error_dots_nonempty")
  skip_if_not_installed("sensitivity")
  m <- screen_morris(bem_simulator(shipped_epw(2013)), r = 3, seed = 1)
  expect_identical(plot(m)$data, plot_morris(m)$data)
})
