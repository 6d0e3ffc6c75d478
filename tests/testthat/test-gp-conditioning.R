# The Gaussian-process conditionals for one draw (R/gp-conditioning.R)
# against brute-force dense computations (helper-reference.R).

test_that("conditioning equals a brute-force dense computation on a tiny problem", {
  withr::local_seed(3)
  n <- 4
  x <- matrix(runif(n * 2), n, 2, dimnames = list(NULL, c("a", "b")))
  design <- cbind(k = c(0.2, 1.5, 2.8))
  sim <- do.call(rbind, lapply(1:3, function(r) data.frame(eta = rnorm(n), x, k = design[r])))
  field <- data.frame(y = rnorm(n), x)
  # a grid over the field inputs, and one with a further input (held out)
  # with the linear emulator mean (1, a, b, k; with days, 1 + p + q), and the paper's zero mean
  # periods of different lengths (input `days`): each row's noise its own
  days <- c(28, 31, 30, 34)
  sim_days <- cbind(sim, days = rep(days, 3))[c("eta", "a", "b", "days", "k")]
  cases <- list(list(d = koh_data(field, sim), priors = koh_priors()),
                list(d = koh_data(field[1:3, ], sim), priors = koh_priors()),
                list(d = koh_data(field, sim), priors = koh_priors(emulator_mean = "zero")),
                list(d = koh_data(cbind(field, days = days), sim_days), priors = koh_priors()))
  for (case in cases) {
    d <- case$d
    expect_false(is.null(d$grid))
    sd <- bayesbem:::koh_stan_data(d, case$priors)
    expect_equal(sd$n_b, if (case$priors$emulator_mean == "zero") 0 else 1 + d$p + d$q)
    # new rows off the data and on a field input, where the jitter applies
    x_new <- rbind(matrix(runif(3 * d$p), 3, d$p), d$xf[2, ], d$xc[4, ])
    for (structure in c("dense", "grid")) {
      g <- bayesbem:::gp_geometry(d, x_new, structure)
      for (i in 1:3) {
        pars <- random_koh_pars(sd)
        ours <- bayesbem:::koh_conditional(g, as_draw_pars(pars, sd$nugget, sd))
        brute <- reference_conditional(sd, pars, x_new)
        expect_equal(ours$mean, brute$mean, tolerance = 1e-8)
        expect_equal(ours$cov, brute$cov, tolerance = 1e-8)
      }
    }
  }
})

test_that("predictive draws come from a Cholesky factor, the same on every machine", {
  cov <- matrix(c(4, 1, 0, 1, 3, 1, 0, 1, 2), 3)
  z <- withr::with_seed(3, rnorm(3))
  expect_equal(withr::with_seed(3, bayesbem:::rmvnorm_psd(1:3, cov)),
               1:3 + drop(t(chol(cov)) %*% z))
  # a covariance whose eigenvectors are not unique (equal eigenvalues) moves
  # the draw only by its own change, however LAPACK would order and sign them
  near <- diag(2) + matrix(c(0, 1e-13, 1e-13, 0), 2)
  expect_equal(withr::with_seed(4, bayesbem:::rmvnorm_psd(c(0, 0), near)),
               withr::with_seed(4, bayesbem:::rmvnorm_psd(c(0, 0), diag(2))), tolerance = 1e-10)
  # singular to rounding (rank one): draws lie on the line
  v <- c(1, 2)
  draw <- withr::with_seed(5, bayesbem:::rmvnorm_psd(c(0, 0), tcrossprod(v) - 1e-15 * diag(2)))
  expect_equal(draw[2] / draw[1], 2, tolerance = 1e-4)
})
