test_that("extend() adds discrepancy terms with coefficients in output units", {
  skip_on_cran()
  case <- synthetic_case("step")
  ext <- synthetic_extension("step", "after_change")
  expect_s3_class(ext, "bayesbem_fit")
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

test_that("a region named by explain_discrepancy() becomes a covariate in its own units", {
  d <- seb_fit$data
  temp <- d$field$temp
  occupancy <- data.frame(occupancy = seq(0.1, 1.2, by = 0.1))
  # a line in occupancy where temp > 10 is its step there and occupancy there
  terms <- bayesbem:::extension_covariates(d, c("occupancy, where temp > 10", "temp > 10",
                                                "occupancy:temp<10"), occupancy)
  expect_named(terms, c("temp>10", "occupancy:temp>10", "temp<10", "occupancy:temp<10"))
  expect_equal(terms[[1]], as.numeric(temp > 10))
  expect_equal(terms[[2]], occupancy$occupancy * (temp > 10))
  expect_equal(terms[[3]], as.numeric(temp <= 10))
  expect_equal(terms[[4]], occupancy$occupancy * (temp <= 10))
  # the name must name columns there are
  expect_error(bayesbem:::extension_covariates(d, "people, where temp > 10", occupancy),
               class = "bayesbem_error_columns")
})

test_that("a hinge becomes a covariate in its input's units, and its name defines it", {
  d <- seb_fit$data
  temp <- d$field$temp
  terms <- bayesbem:::extension_covariates(d, c("max(temp - 12, 0)", "max(5 - temp, 0)",
                                                "max(temp + 2.5, 0)"), NULL)
  expect_named(terms, c("max(temp-12,0)", "max(5-temp,0)", "max(temp+2.5,0)"))
  expect_equal(terms[[1]], pmax(temp - 12, 0))
  expect_equal(terms[[2]], pmax(5 - temp, 0))
  expect_equal(terms[[3]], pmax(temp + 2.5, 0))
  # the column name rebuilds the same values (predict() from newdata)
  new <- data.frame(temp = c(-3, 8, 30))
  expect_equal(bayesbem:::region_values("max(temp-12,0)", new), c(0, 0, 18))
  expect_equal(bayesbem:::term_variables("max(5 - temp, 0)"), "temp")
  expect_null(bayesbem:::parse_hinge("max(temp, 0)"))
  expect_error(bayesbem:::extension_covariates(d, "max(people - 3, 0)", NULL),
               class = "bayesbem_error_columns")
})

test_that("region thresholds split as the quantiles do, and their names define them", {
  x <- c(0.1, 1.06, 1.7, 3.9, 4.4, 6.1, 8.9, 10.3, 10.3, 12.1, 14.12, 15.4, 18.8, 21.4, 22.3,
         22.6, 23.2, 23.8)
  cuts <- bayesbem:::region_cuts(x)
  q <- stats::quantile(x, c(1, 1.5, 2, 2.5, 3) / 4, names = FALSE)
  kept <- vapply(q, function(v) min(sum(x > v), sum(x <= v)) >= 5, logical(1))
  expect_equal(lapply(cuts, function(cut) x > cut), unique(lapply(q[kept], function(v) x > v)))
  # shortest decimals: 10.3 < 11 < 12.1 for the median 11.2, 4.4 < 5 < 6.1, ...
  expect_equal(cuts, c(5, 10, 11, 15, 20))
  terms <- bayesbem:::region_terms(data.frame(x = x, w = x^2), data.frame(x = x))
  # a line in w on one side: its step and w there
  expect_equal(unname(terms[["w, where x > 11"]]), cbind(as.numeric(x > 11), x^2 * (x > 11)))
  expect_equal(unname(terms[["w, where x < 11"]]), cbind(as.numeric(x <= 11), x^2 * (x <= 11)))
  expect_equal(drop(terms[["x > 11"]]), as.numeric(x > 11))
  # hinges on both sides of each cut, in x's units
  expect_equal(drop(terms[["max(x - 11, 0)"]]), pmax(x - 11, 0))
  expect_equal(drop(terms[["max(11 - x, 0)"]]), pmax(11 - x, 0))
  expect_length(terms, length(cuts) * 5)
  expect_identical(bayesbem:::hinge_label("x", c(">", ">", "<"), c(11, -2.5, -2.5)),
                   c("max(x - 11, 0)", "max(x + 2.5, 0)", "max(-2.5 - x, 0)"))
  for (label in c("max(x + 2.5, 0)", "max(-2.5 - x, 0)")) {
    expect_equal(bayesbem:::parse_hinge(label)$cut, -2.5)
  }
})

test_that("an extension by a region predicts from the inputs it names", {
  skip_on_cran()
  case <- synthetic_case("interaction")
  ext <- synthetic_extension("interaction", "occupancy, where temp > 15")
  expect_equal(names(ext$data$covariates), c("temp>15", "occupancy:temp>15"))
  # the hidden effect is 300 kWh per unit of occupancy where temp > 15
  gamma <- posterior::as_draws_df(ext)$`gamma[occupancy:temp>15]`
  expect_gt(mean(gamma), 200)
  expect_lt(mean(gamma), 400)
  # predictions rebuild the columns from occupancy and temp
  given <- case$holdout
  given[["temp>15"]] <- as.numeric(given$temp > 15)
  given[["occupancy:temp>15"]] <- given$occupancy * (given$temp > 15)
  draws <- function(newdata) {
    suppressWarnings(withr::with_seed(1, bayesbem:::predict_draws(ext, newdata, ndraws = 20)),
                     classes = "bayesbem_warning_extrapolation")
  }
  expect_equal(draws(case$holdout), draws(given))
})

test_that("extend() puts the terms on one output's discrepancy of a fit on several", {
  skip_on_cran()
  fit <- two_output_fit()
  n_gas <- output_fit(fit, "gas")$data$n
  change <- data.frame(after_change = as.numeric(seq_len(n_gas) > 6))
  ext <- suppressWarnings(extend(fit, with = "after_change", covariates = change, output = "gas"))
  expect_s3_class(ext, "bayesbem_fit_outputs")
  gas <- posterior::variables(posterior::as_draws(output_fit(ext, "gas")))
  electricity <- posterior::variables(posterior::as_draws(output_fit(ext, "electricity")))
  expect_true("gamma[after_change]" %in% gas)
  expect_false(any(startsWith(electricity, "gamma")))
  expect_equal(output_fit(ext, "gas")$data$covariates$after_change, change$after_change)
  expect_error(extend(fit, with = "after_change", covariates = change),
               class = "bayesbem_error_argument")
  expect_error(extend(seb_fit, with = "temp", output = "gas"), class = "bayesbem_error_argument")
})
