# The noise's covariance and draws (R/gp-noise.R): AR(1) algebra against its
# dense correlation matrix, draws against their moments.

test_that("the Gram matrices of AR(1) noise weigh rows by the inverse correlation", {
  withr::local_seed(41)
  segments <- c(1, 1, 1, 1, 2, 3, 3)
  z <- matrix(stats::rnorm(7 * 3), 7)
  ar <- bayesbem:::ar1_grams(z, segments)
  expect_equal(ar$segments, 3)
  for (phi in c(-0.4, 0.3, 0.95)) {
    expect_equal(bayesbem:::ar1_weighted(crossprod(z), ar, phi),
                 t(z) %*% solve(reference_ar1_cor(phi, segments), z))
    # log|R| = (rows - segments) log(1 - phi^2)
    expect_equal(determinant(reference_ar1_cor(phi, segments))$modulus[[1]],
                 (7 - 3) * log(1 - phi^2))
  }
})

test_that("AR(1) noise series have unit variance, lag-1 correlation phi, and restart by segment", {
  withr::local_seed(42)
  segments <- rep(1:2, each = 3)
  x <- t(replicate(20000, bayesbem:::ar1_series(0.8, segments)))
  # a sample correlation's standard error is below 1 / sqrt(20000) = 0.007
  expect_equal(apply(x, 2, stats::var), rep(1, 6), tolerance = 0.05)
  expect_equal(stats::cor(x[, 1], x[, 2]), 0.8, tolerance = 0.03)
  expect_equal(stats::cor(x[, 1], x[, 3]), 0.64, tolerance = 0.03)
  expect_lt(abs(stats::cor(x[, 3], x[, 4])), 0.03)
  draws <- list(list(lambda_e = 4, phi = 0.8), list(lambda_e = 4, phi = 0))
  noise <- bayesbem:::noise_matrix(draws, rep(1, 6), segments)
  expect_equal(dim(noise), c(2, 6))
})

test_that("the dense noise covariance carries the AR(1) correlation", {
  g <- list(noise = c(1, 1, 2, 2), segments = c(1, 1, 1, 2))
  expect_equal(bayesbem:::noise_cov(g, list(lambda_e = 4)), diag(c(1, 1, 2, 2) / 4))
  v <- 0.1 + c(1, 1, 2, 2) / 4
  expect_equal(bayesbem:::noise_cov(g, list(lambda_e = 4, phi = 0.6), extra = 0.1),
               reference_ar1_cor(0.6, g$segments) * outer(sqrt(v), sqrt(v)))
})

test_that("month shifts: the training months' given, new months' from the prior, one per month", {
  withr::local_seed(5)
  draws <- lapply(1:4000, function(i) list(lambda_shift = 25))
  known <- matrix(rep(c(0.3, -0.1), each = 4000), 4000, dimnames = list(NULL, c("2019-01", "2019-02")))
  labels <- c("2019-02", "2019-10", "2019-10", "2019-11", "2019-01")
  l <- bayesbem:::shift_matrix(draws, labels, known)
  expect_equal(l[, 1], known[, "2019-02"], ignore_attr = TRUE)
  expect_equal(l[, 5], known[, "2019-01"], ignore_attr = TRUE)
  # a new month's periods share its shift; months are independent, sd 1 / 5
  expect_equal(l[, 2], l[, 3])
  expect_equal(stats::sd(l[, 2]), 0.2, tolerance = 0.05)
  expect_lt(abs(stats::cor(l[, 2], l[, 4])), 0.06)
  # noise adds them to the white noise
  e <- bayesbem:::noise_matrix(lapply(draws, c, lambda_e = 100), rep(1, 5), months = labels,
                               known = known)
  expect_equal(stats::sd(e[, 2]), sqrt(0.04 + 0.01), tolerance = 0.05)
  expect_equal(stats::cov(e[, 2], e[, 3]), 0.04, tolerance = 0.1)
})
