test_that("the Hilbert-space basis approximates the additive kernel over the length scales", {
  # two inputs on [0, 1]; rho_delta from short (0.02) to long length
  # scales, the longest held at rho_delta = 0.98's
  withr::local_seed(5)
  x <- matrix(stats::runif(120), ncol = 2)
  design <- bayesbem:::hsgp_design()
  pair <- bayesbem:::pair_geometry(x, x)
  for (rho in c(0.02, 0.1, 0.5, 0.9, 0.98, 0.999, 1 - 1e-9)) {
    beta <- -4 * log(c(rho, 0.5))
    exact <- bayesbem:::delta_cov(pair, list(beta_delta = beta, lambda_delta = 2, additive = TRUE))
    approx <- bayesbem:::hsgp_cov(x, x, design, beta, 2)
    # the kernel's variance is 1 / lambda = 0.5
    expect_lt(max(abs(exact - approx)), 0.025 * 0.5, label = paste("rho", rho))
  }
  # the additive kernel: the mean of one squared-exponential kernel per
  # input, beta floored smoothly at 0.08 (rho_delta 0.98)
  k <- bayesbem:::delta_cov(pair, list(beta_delta = c(3, 0), lambda_delta = 2, additive = TRUE))
  expect_equal(k[2, 7], (exp(-sqrt(9 + 0.08^2) * (x[2, 1] - x[7, 1])^2) +
                           exp(-0.08 * (x[2, 2] - x[7, 2])^2)) / 4)
  # the basis functions: input 1's first, each a sine on [-L, L] about 1/2
  phi <- bayesbem:::hsgp_phi(x, design)
  expect_equal(dim(phi), c(60, 2 * design$m))
  L <- design$half_width
  expect_equal(phi[3, design$m + 2], sin(pi * 2 * (x[3, 2] - 0.5 + L) / (2 * L)) / sqrt(L))
})
