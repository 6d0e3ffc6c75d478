test_that("predictions at the training inputs reproduce the field data", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(1)
  p <- predict(fit, noise = TRUE)
  expect_named(p, c("temp", "rh", "solar", "mean", "sd", "q5", "q50", "q95"))
  expect_equal(nrow(p), 12)
  inside <- seb_field$y >= p$q5 & seb_field$y <= p$q95
  expect_gte(sum(inside), 10)
  expect_lt(max(abs(p$mean - seb_field$y) / seb_field$y), 0.1)
})

test_that("y is eta plus delta, draw by draw", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(2)
  d <- bayesbem:::predict_draws(fit, seb_field[2:4], ndraws = 100)
  expect_equal(d$y, d$eta + d$delta)
  expect_equal(dim(d$y), c(100, 12))
  means <- vapply(c("y", "eta", "delta"), function(type) {
    withr::with_seed(5, predict(fit, type = type, ndraws = 100)$mean)
  }, numeric(12))
  expect_equal(means[, "y"], means[, "eta"] + means[, "delta"])
  draws <- predict(fit, type = "delta", ndraws = 30, summary = FALSE)
  expect_equal(dim(draws), c(30, 12))
})

test_that("the conditional and the sampled (Appendix D) routes agree", {
  skip_on_cran()
  fit <- sampled_fit()
  sampled <- predict(fit, method = "sampled")
  expect_equal(sampled[c("temp", "rh", "solar")], shared_predict_at(), ignore_attr = TRUE)
  # Rao-Blackwellised conditional means over the same posterior draws
  x_new <- bayesbem:::scale_newdata(fit$data, shared_predict_at())
  g <- bayesbem:::gp_geometry(fit$data, x_new, "dense")
  cond <- vapply(bayesbem:::draw_parameters(fit), function(par) {
    mu <- bayesbem:::koh_conditional(g, par)$mean
    mu[1:3] + mu[4:6]
  }, numeric(3))
  cond_mean <- bayesbem:::unscale_y(rowMeans(cond), fit$data$scaling)
  expect_lt(max(abs(cond_mean - sampled$mean) / sampled$sd), 0.1)
})

test_that("newdata is checked: extrapolation warns, wrong columns fail", {
  skip_on_cran()
  fit <- shared_fit()
  hot <- data.frame(temp = 35, rh = 40, solar = 250)
  expect_warning(predict(fit, hot, ndraws = 20), class = "bayesbem_warning_extrapolation")
  expect_error(predict(fit, data.frame(temp = 1, rh = 2)), class = "bayesbem_error_columns")
  expect_snapshot(predict(fit, data.frame(temp = 1, rh = 2)), error = TRUE)
  expect_snapshot(predict(sampled_fit(), type = "eta", method = "sampled"), error = TRUE)
})

test_that("predict() rejects unknown arguments and types with classed errors", {
  withr::local_options(cli.num_colors = 1)
  expect_error(predict(seb_fit, n_draws = 10), class = "rlib_error_dots_nonempty")
  expect_error(predict(seb_fit, type = "dleta"), class = "bayesbem_error_argument")
  expect_snapshot(predict(seb_fit, type = "dleta"), error = TRUE)
  expect_snapshot(predict(seb_fit, method = 2), error = TRUE)
  expect_snapshot(plot(seb_fit, type = "trace plot"), error = TRUE)
  expect_snapshot(plot(seb_fit, type = "trace", variable = "lambda_e"), error = TRUE)
  expect_snapshot(prior_strength("strong"), error = TRUE)
  expect_s3_class(plot(seb_fit, type = "trace", variables = "lambda_e"), "ggplot")
})
