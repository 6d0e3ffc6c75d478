# The vignette's precomputed studies (inst/extdata): fixed numbers, so the
# drawings are the same on every machine.
shipped_studies <- function() {
  readRDS(system.file("extdata", "vignette-studies.rds", package = "bayesbem"))
}

test_that("plot_parameter_study() draws each parameter's posterior by k", {
  study <- shipped_studies()$parameter_study
  d <- plot_parameter_study_data(study)
  expect_equal(levels(d$k), as.character(study$k))
  expect_equal(levels(d$parameter), study$ranking[study$ranking %in% d$parameter])
  expect_identical(plot(study)$data, d)
  expect_error(plot_parameter_study(seb_fit), class = "bayesbem_error_argument")
  skip_if_not_installed("vdiffr")
  vdiffr::expect_doppelganger("parameter-study", plot_parameter_study(study))
})

test_that("plot_prior_study() draws each strength's posterior density", {
  study <- shipped_studies()$prior_study
  expect_identical(plot_prior_study_data(study), study$densities)
  expect_error(plot_prior_study(seb_fit), class = "bayesbem_error_argument")
  skip_if_not_installed("vdiffr")
  vdiffr::expect_doppelganger("prior-study", plot_prior_study(study))
})
