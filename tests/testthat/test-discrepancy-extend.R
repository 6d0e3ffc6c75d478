test_that("extend() adds discrepancy terms with coefficients in output units", {
  skip_on_cran()
  case <- synthetic_case("step")
  ext <- synthetic_extension("step", "after_change")
  expect_s3_class(ext, "koh_fit")
  expect_equal(names(ext$data$covariates), "after_change")
  draws <- posterior::as_draws_df(ext)
  # the hidden step is 200 kWh
  expect_gt(mean(draws$`gamma[after_change]`), 100)
  expect_lt(mean(draws$`gamma[after_change]`), 300)
  # predictions need the covariate; y is still eta + delta draw by draw
  expect_error(predict(ext, case$holdout[c("temp", "rh", "solar")]),
               class = "bayesbem_error_columns")
  p <- suppressWarnings(bayesbem:::predict_draws(ext, case$holdout, ndraws = 20),
                        classes = "bayesbem_warning_extrapolation")
  expect_equal(p$y, p$eta + p$delta)
})

test_that("the grid conditional handles discrepancy terms like the dense one", {
  skip_on_cran()
  ext <- synthetic_extension("step", "after_change")
  x_new <- ext$data$xf[1:3, ] * 0.9
  pars <- bayesbem:::draw_parameters(ext, 3)
  for (par in pars) {
    dense <- bayesbem:::koh_conditional(bayesbem:::gp_geometry(ext$data, x_new, "dense"), par)
    grid <- bayesbem:::koh_conditional(bayesbem:::gp_geometry(ext$data, x_new, "grid"), par)
    expect_equal(grid$mean, dense$mean, tolerance = 1e-6)
    expect_equal(grid$cov, dense$cov, tolerance = 1e-6)
  }
})

test_that("extend() checks what it is given", {
  expect_error(extend(seb_fit), class = "bayesbem_error_argument")
  expect_snapshot(extend(seb_fit), error = TRUE)
  expect_snapshot(extend(seb_fit, with = "occupancy"), error = TRUE)
  expect_error(extend(seb_fit, with = "k", covariates = data.frame(k = 1:3)),
               class = "bayesbem_error_covariates")
  expect_error(extend(1, with = "rh"), class = "bayesbem_error_argument")
})

test_that("covariates are divided by their range, not centred", {
  d <- koh_data(seb_field, seb_sim)
  working <- data.frame(working_days = c(21, 20, 21, 22, 23, 20, 23, 22, 21, 23, 20, 21))
  ext <- bayesbem:::add_discrepancy_terms(d, working)
  expect_equal(ext$h_scale, c(working_days = 3))
  expect_equal(drop(ext$h), working$working_days / 3)
  # the same covariate in other units gets the same prior strength
  hours <- bayesbem:::add_discrepancy_terms(d, data.frame(working_days = working$working_days * 8))
  expect_equal(hours$h, ext$h)
})
