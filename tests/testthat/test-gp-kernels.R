# The kernels in R (R/gp-kernels.R) against their formulas written out
# element by element (method.md section 1).

test_that("the correlations and the discrepancy's covariance are the squared-exponential kernels", {
  withr::local_seed(2)
  a <- matrix(stats::runif(8), 4, 2)
  b <- rbind(a[3, ], matrix(stats::runif(4), 2, 2))
  pair <- bayesbem:::pair_geometry(a, b)
  beta <- c(1.5, 4)
  nugget <- 1e-6
  cor <- bayesbem:::jittered_cor(pair, beta, nugget)
  product <- bayesbem:::delta_cov(pair, list(beta_delta = beta, lambda_delta = 3))
  additive <- bayesbem:::delta_cov(pair, list(beta_delta = beta, lambda_delta = 3, additive = TRUE))
  for (i in seq_len(nrow(a))) {
    for (j in seq_len(nrow(b))) {
      d2 <- (a[i, ] - b[j, ])^2
      same <- all(a[i, ] == b[j, ])
      expect_equal(cor[i, j], exp(-sum(beta * d2)) + nugget * same)
      expect_equal(product[i, j], exp(-sum(beta * d2)) / 3)
      # the mean of one kernel per input, each beta floored at 0.08
      expect_equal(additive[i, j], mean(exp(-sqrt(beta^2 + 0.08^2) * d2)) / 3)
    }
  }
  # the jitter only where rows are equal: a's third row is b's first
  expect_identical(which(pair$eq == 1, arr.ind = TRUE)[1, ], c(row = 3L, col = 1L))
  expect_equal(sum(pair$eq), 1)
})

test_that("the t distances and the emulator mean are their sums", {
  withr::local_seed(3)
  tc <- matrix(stats::runif(6), 3, 2)
  tf <- c(0.2, 0.7)
  beta_t <- c(2, 0.5)
  expect_equal(bayesbem:::tf_distance(tc, tf, beta_t),
               vapply(1:3, function(r) sum(beta_t * (tc[r, ] - tf)^2), numeric(1)))
  x <- matrix(stats::runif(4), 2, 2)
  coef <- c(1, 2, -1, 0.5, 3)
  # h(x, t)' b = b0 + x' b_x + t' b_t, at one t or each row's own
  expect_equal(bayesbem:::emulator_mean(x, tf, coef),
               drop(1 + x %*% c(2, -1) + sum(tf * c(0.5, 3))))
  expect_equal(bayesbem:::emulator_mean(x, tc[1:2, ], coef),
               drop(1 + x %*% c(2, -1) + tc[1:2, ] %*% c(0.5, 3)))
  # on a grid: element (i, a) at grid input i and run a
  grid <- bayesbem:::grid_mean(x, tc, coef)
  expect_equal(grid[2, 3], bayesbem:::emulator_mean(x[2, , drop = FALSE], tc[3, ], coef))
  expect_equal(dim(grid), c(2L, 3L))
})
