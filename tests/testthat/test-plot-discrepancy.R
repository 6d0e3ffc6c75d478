test_that("plot_discrepancy() shows delta along each input and in point order", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(12)
  d <- discrepancy(fit, ndraws = 200)
  pd <- plot_discrepancy_data(d)
  expect_equal(levels(pd$along), c("temp", "rh", "solar", "point order"))
  expect_equal(nrow(pd), 4 * 12)
  expect_equal(pd$position[pd$along == "rh"], seb_field$rh)
  expect_s3_class(plot_discrepancy(d), "ggplot")
  expect_error(plot_discrepancy_data(data.frame()), class = "bayesbem_error_argument")
})

# drawn from the shipped seb_fit with a fixed seed: the same on every machine
test_that("plot_discrepancy() draws", {
  skip_if_not_installed("vdiffr")
  withr::local_seed(12)
  vdiffr::expect_doppelganger("discrepancy", plot_discrepancy(discrepancy(seb_fit, ndraws = 100)))
})
