# The noise of periods of different lengths (R/data-noise.R); the programs'
# densities with each row's noise are checked against the references in
# test-fit.R, test-fit-basis.R and test-predict.R (random_grid_data(days = TRUE)).

test_that("a period's total of independent daily errors has variance proportional to its days", {
  withr::local_seed(1)
  days <- c(7, 26, 30, 34, 61)
  totals <- vapply(days, function(k) colSums(matrix(stats::rnorm(k * 4000, sd = 2), k)),
                   numeric(4000))
  x <- data.frame(days = days)
  w <- bayesbem:::period_weights(x)
  expect_equal(w, days / mean(days))
  # var(total_i) / w_i is one number, the variance of a period of the mean length
  per_weight <- apply(totals, 2, stats::var) / w
  expect_equal(per_weight, rep(4 * mean(days), length(days)), tolerance = 0.1)
})

test_that("koh_data() weighs each period's noise by its days, on the field's mean", {
  withr::local_seed(2)
  d <- random_grid_data(n = 6, extra = 2, days = TRUE)
  days <- d$field$days
  expect_equal(d$scaling$days, mean(days))
  expect_equal(bayesbem:::noise_weights(d), days / mean(days))
  # new periods on the same reference
  expect_equal(bayesbem:::noise_weights(d, data.frame(days = c(15, 60))), c(15, 60) / mean(days))
  expect_match(paste(utils::capture.output(print(d)), collapse = "\n"), "proportional to each period's")
  priors <- koh_priors()
  expect_equal(as.vector(bayesbem:::koh_stan_data(d, priors, structure = "grid")$noise_weight),
               days / mean(days))
  x_pred <- d$xf[1:2, , drop = FALSE]
  dense <- bayesbem:::koh_stan_data(d, priors, x_pred = x_pred)
  expect_equal(as.vector(dense$noise_weight), days / mean(days))
  expect_equal(as.vector(dense$noise_weight_pred), days[1:2] / mean(days))
  # without `days` every weight is 1 (the paper's model)
  plain <- koh_data(seb_field, seb_sim)
  expect_null(plain$scaling$days)
  expect_equal(bayesbem:::noise_weights(plain), rep(1, 12))
})

test_that("each output's periods weigh its own noise", {
  withr::local_seed(3)
  r <- random_outputs_data()
  days <- sample(20:40, nrow(unique(r$sim[c("a", "b")])), replace = TRUE)
  key <- function(t) paste(t$a, t$b)
  lookup <- stats::setNames(days, unique(key(r$sim)))
  r$field$days <- unname(lookup[key(r$field)])
  r$sim$days <- unname(lookup[key(r$sim)])
  d <- koh_data(r$field, r$sim)
  sd <- bayesbem:::stage2_stan_data(d, koh_priors(emulator_mean = "zero"))
  expected <- unlist(lapply(d$outputs, function(o) o$field$days / mean(o$field$days)))
  expect_equal(as.vector(sd$noise_weight), unname(expected))
})

test_that("noise draws and simulated bills grow with the period's days", {
  withr::local_seed(4)
  fit <- list(data = list(scaling = list(y_scale = 2, days = 30)))
  draws <- lapply(c(1, 4), function(l) list(lambda_e = l))
  e <- bayesbem:::noise_draws(fit, draws[rep(1:2, 20000)], data.frame(days = c(15, 60)))
  # sd = y_scale * sqrt(w / lambda_e), draw by draw
  expect_equal(apply(e[c(TRUE, FALSE), ], 2, stats::sd), 2 * sqrt(c(0.5, 2)), tolerance = 0.03)
  expect_equal(apply(e[c(FALSE, TRUE), ], 2, stats::sd), 2 * sqrt(c(0.5, 2) / 4), tolerance = 0.03)

  weather <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
  bills <- data.frame(start = as.Date(c("2013-01-01", "2013-01-08", "2013-03-01")),
                      end = as.Date(c("2013-01-07", "2013-02-28", "2013-03-30")))
  sim <- bem_simulator(weather, periods = bills)
  field <- simulate_field(sim, list(equipment_power_density = 15), noise_sd = 10, seed = 5)
  noise <- field$y - attr(field, "simulated")
  w <- sim$x$days / mean(sim$x$days)
  expect_equal(noise / sqrt(w), withr::with_seed(5, stats::rnorm(3, sd = 10)))
})

test_that("AR(1) segments break at gaps and steps back", {
  t0 <- as.POSIXct("2013-03-09 22:00", tz = "UTC")
  times <- t0 + 3600 * c(0, 1, 2, 4, 5, 5, 6, 3)
  expect_equal(bayesbem:::noise_segments(times), c(1, 1, 1, 2, 2, 3, 3, 4))
  expect_equal(bayesbem:::noise_segments(as.Date("2013-01-01") + c(0:3, 10:11)),
               c(1, 1, 1, 1, 2, 2))
  expect_equal(bayesbem:::noise_segments(t0), 1)
})

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

test_that("months are read in the times' own zone", {
  utc <- as.POSIXct(c("2019-09-30 23:30", "2019-10-01 00:30"), tz = "UTC")
  expect_equal(bayesbem:::period_months(utc), c("2019-09", "2019-10"))
  attr(utc, "tzone") <- "Europe/London"
  expect_equal(bayesbem:::period_months(utc), c("2019-10", "2019-10"))
  expect_equal(bayesbem:::period_months(as.Date(c("2013-01-31", "2013-02-01"))),
               c("2013-01", "2013-02"))
  m <- bayesbem:::shift_columns(c("b", "a", "b"))
  expect_equal(colnames(m), c("a", "b"))
  expect_equal(unname(m), cbind(c(0, 1, 0), c(1, 0, 1)))
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
