# drawn from the shipped seb_fit with a fixed seed: the same on every machine
test_that("plot_identifiability() places each parameter by what the data taught", {
  withr::local_seed(3)
  x <- identifiability(seb_fit, ndraws = 50)
  d <- plot_identifiability_data(x)
  expect_equal(d$abs_shift, pmax(abs(x$shift), 0.01))
  expect_equal(levels(d$verdict), c("learnt", "partly learnt", "prior-driven",
                                    "confounded with the discrepancy"))
  expect_identical(plot(x)$data, d)
  expect_error(plot_identifiability_data(seb_fit), class = "bayesbem_error_argument")
  skip_if_not_installed("vdiffr")
  vdiffr::expect_doppelganger("identifiability", plot_identifiability(x))
})
