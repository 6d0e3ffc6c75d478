test_that("extending the model with the true cause helps, measurably", {
  skip_on_cran()
  # a humidity cause is added as a flag of the humid months ("humid")
  terms <- c(input = "humid", covariate = "occupancy", step = "after_change")
  for (kind in names(terms)) {
    case <- synthetic_case(kind)
    ext <- synthetic_extension(kind, terms[[kind]])
    cmp <- suppressWarnings(compare_fits(case$base, ext, newdata = case$holdout,
                                         obs = case$holdout$y, truth = synthetic_truth),
                            classes = "bayesbem_warning_extrapolation")
    expect_s3_class(cmp, "bayesbem_comparison")
    expect_gt(cmp$elpd$diff, 2 * cmp$elpd$se, label = kind)
    held <- cmp$metrics[cmp$metrics$set == "held-out", ]
    expect_lt(held$cvrmse[held$fit == "b"], held$cvrmse[held$fit == "a"], label = kind)
    expect_equal(cmp$bias$parameter, names(synthetic_truth))
    expect_match(cmp$verdict, "^b predicts better")
  }
})

test_that("extending the model shrinks the bias of the confounded parameter", {
  skip_on_cran()
  terms <- c(input = "humid", covariate = "occupancy", step = "after_change")
  for (kind in names(terms)) {
    cmp <- compare_fits(synthetic_case(kind)$base, synthetic_extension(kind, terms[[kind]]),
                        truth = synthetic_truth)
    # every effect adds energy, which a higher equipment power density mimics
    # (which parameter a seeded fit leaves most biased depends on the
    # chains' path, so only the direction and the shrinkage are asserted)
    epd <- cmp$bias[cmp$bias$parameter == "equipment_power_density", ]
    expect_gt(epd$bias_a, 0, label = kind)
    expect_lt(abs(epd$bias_b), abs(epd$bias_a) / 2, label = kind)
  }
})

test_that("on a correct simulator, extending the model brings no gain", {
  skip_on_cran()
  case <- synthetic_case("none")
  ext <- synthetic_extension("none", "occupancy")
  cmp <- suppressWarnings(compare_fits(case$base, ext, newdata = case$holdout,
                                       obs = case$holdout$y),
                          classes = "bayesbem_warning_extrapolation")
  # no gain: an unneeded term costs a little predictive density, at most
  expect_lt(cmp$elpd$diff, 2 * cmp$elpd$se)
  expect_false(grepl("^b predicts better", cmp$verdict))
  expect_null(cmp$bias)
})

test_that("leave-one-out is exact for the Gaussian likelihood", {
  skip_on_cran()
  fit <- shared_fit()
  # log p(y_i | y_-i, eta) for one draw against conditioning with solve()
  par <- bayesbem:::draw_parameters(fit, 1)[[1]]
  g <- bayesbem:::gp_geometry(fit$data, structure = "dense")
  sigma <- bayesbem:::koh_sigma_z(g, par)
  # less the emulator mean [1, x, t] . coef of every row (field rows at tf)
  d <- fit$data
  u <- rbind(cbind(1, d$xf, matrix(par$tf, d$n, d$q, byrow = TRUE)), cbind(1, d$xc, d$tc))
  z <- c(d$y, d$eta) - drop(u %*% par$coef)
  i <- 5
  s12 <- sigma[i, -i]
  mu <- s12 %*% solve(sigma[-i, -i], z[-i])
  v <- sigma[i, i] - s12 %*% solve(sigma[-i, -i], s12)
  expect_equal(bayesbem:::loo_log_density(g, par)[i],
               stats::dnorm(z[i], mu, sqrt(v), log = TRUE), tolerance = 1e-8)
  # with 200 draws loo warns of high Pareto k; only the object's form is tested here
  l <- suppressWarnings(loo::loo(fit, ndraws = 200))
  expect_s3_class(l, "psis_loo")
  expect_equal(dim(l$pointwise)[1], 12)
})

test_that("compare_fits() needs fits of the same data", {
  other <- seb_fit
  other$data$field$y[1] <- other$data$field$y[1] + 1
  expect_error(compare_fits(seb_fit, other), class = "bayesbem_error_argument")
  expect_snapshot(compare_fits(seb_fit, other), error = TRUE)
})
