test_that("run_case_study() prints the fit, its diagnostics and metrics, and saves three plots", {
  skip_on_cran()
  dir <- withr::local_tempdir()
  # a short run, so the convergence warning is expected
  expect_warning(
    expect_message(
      out <- capture.output(
        fit <- run_case_study(chains = 1, iter = 200, seed = test_seed(2018), cores = 1,
                              plot_dir = dir)
      ),
      "Plots saved"
    ),
    class = "bayesbem_warning_convergence"
  )
  expect_s3_class(fit, "bayesbem_fit")
  expect_equal(fit$settings$structure, "grid")
  expect_true(any(grepl("ASHRAE Guideline 14", out)))
  expect_true(any(grepl("equipment_power_density", out)))
  expect_setequal(list.files(dir), c("posteriors.png", "components.png", "trace.png"))
})
