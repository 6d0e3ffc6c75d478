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

test_that("stage 2 with the additive discrepancy has the log density of its dense model", {
  skip_on_cran()
  withr::local_seed(23)
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  priors <- koh_priors(tf = list(k1 = prior_normal(1.5, 0.2)))
  basis <- bayesbem:::basis_emulator(d, variance = 0.99)
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                   b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))), basis = basis)
  design <- bayesbem:::hsgp_design(m = 6, boundary = 3)
  sd <- bayesbem:::basis_stan_data(d, priors, emulator, design)
  expect_equal(sd$hsgp, 1L)
  expect_equal(dim(sd$gram), rep(ncol(basis$B) + 6 * d$p + 1 + sd$n_h, 2))
  model <- koh_model_for(sd, "koh_basis")
  kernel <- reference_hsgp_kernel(6, 3)
  for (i in 1:3) {
    pars <- list(tf = as.array(stats::runif(d$q, 0.05, 0.95)),
                 rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
                 lambda_delta = stats::rgamma(1, 10, 0.3), lambda_e = stats::rgamma(1, 10, 0.03),
                 gamma = as.array(stats::rnorm(sd$n_h)))
    ref <- reference_basis(sd, basis, pars, kernel)
    u <- bayesbem:::linear_box_inverse(pars$tf)
    stan_pars <- stage2_pars(c(list(tf_u = as.array(u)), pars[names(pars) != "tf"]))
    a <- sd$tf_edge
    jacobian <- sum(log(stats::plogis(u / a) - stats::plogis((u - 1) / a)))
    expect_equal(basis_log_density(model, sd, stan_pars), ref$lp + jacobian, tolerance = 1e-8)
  }
})

test_that("stage 2 with AR(1) noise has the log density of its dense model", {
  skip_on_cran()
  withr::local_seed(24)
  case <- ar1_basis_case()
  d <- case$data
  basis <- case$basis
  segments <- case$segments
  sd <- case$sd
  expect_equal(c(sd$ar, sd$n_seg), c(1, 2))
  model <- koh_model_for(sd, "koh_basis")
  kernel <- reference_hsgp_kernel(6, 3)
  for (phi in c(-0.3, 0.6, 0.97)) {
    pars <- list(tf = as.array(stats::runif(d$q, 0.05, 0.95)),
                 rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
                 lambda_delta = stats::rgamma(1, 10, 0.3), lambda_e = stats::rgamma(1, 10, 0.03),
                 gamma = numeric(0), phi = phi)
    ref <- reference_basis(sd, basis, pars, kernel, reference_ar1_cor(phi, segments))
    u <- bayesbem:::linear_box_inverse(pars$tf)
    stan_pars <- stage2_pars(c(list(tf_u = as.array(u)), pars[names(pars) != "tf"]))
    a <- sd$tf_edge
    jacobian <- sum(log(stats::plogis(u / a) - stats::plogis((u - 1) / a)))
    # phi's prior is flat on (-1, 1)
    expect_equal(basis_log_density(model, sd, stan_pars), ref$lp + jacobian,
                 tolerance = 1e-8, label = paste("phi", phi))
  }
})

test_that("stage 2 with a shift per month has the log density of its dense model", {
  skip_on_cran()
  withr::local_seed(25)
  case <- ar1_basis_case()
  d <- case$data
  # three months over the nine rows, one of them a single row
  months <- rep(c("2013-07", "2013-08", "2013-09"), c(4, 4, 1))
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                   b = numeric(sum(bayesbem:::mean_selection(koh_priors(), d$p, d$q))),
                   basis = case$basis)
  design <- bayesbem:::hsgp_design(m = 6, boundary = 3)
  same_month <- outer(months, months, "==")
  kernel <- reference_hsgp_kernel(6, 3)
  for (ar in c(FALSE, TRUE)) {
    segments <- if (ar) bayesbem:::output_segments(d)
    sd <- bayesbem:::basis_stan_data(d, koh_priors(), emulator, design, segments, list(months))
    expect_equal(sd$n_shift, 3L)
    # Z = [B, Phi, M, r, h]: the month columns' Gram block counts each month's rows
    lev <- ncol(case$basis$B) + 6 * d$p + 1:3
    expect_equal(unname(diag(sd$gram)[lev]), c(4, 4, 1))
    model <- koh_model_for(sd, "koh_basis")
    for (i in 1:2) {
      pars <- list(tf = as.array(stats::runif(d$q, 0.05, 0.95)),
                   rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
                   lambda_delta = stats::rgamma(1, 10, 0.3), lambda_e = stats::rgamma(1, 10, 0.03),
                   gamma = numeric(0), phi = if (ar) stats::runif(1, -0.5, 0.9),
                   lambda_shift = stats::rgamma(1, 2, 0.05))
      noise_cor <- if (ar) reference_ar1_cor(pars$phi, case$segments) else diag(sd$n)
      ref <- reference_basis(sd, case$basis, pars, kernel, noise_cor,
                             extra_cov = same_month / pars$lambda_shift)
      u <- bayesbem:::linear_box_inverse(pars$tf)
      stan_pars <- stage2_pars(c(list(tf_u = as.array(u)), pars[names(pars) != "tf"]))
      jacobian <- sum(log(stats::plogis(u / sd$tf_edge) - stats::plogis((u - 1) / sd$tf_edge)))
      prior <- stats::dgamma(pars$lambda_shift, 1, 0.01, log = TRUE)
      expect_equal(basis_log_density(model, sd, stan_pars), ref$lp + jacobian + prior,
                   tolerance = 1e-8, label = paste("AR(1)", ar))
    }
  }
})

test_that("the additive discrepancy needs the basis emulator and periods of one length", {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  expect_identical(bayesbem:::choose_discrepancy_kernel("additive", "basis", d), "additive")
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", d), "product")
  # "auto": additive above 400 rows, with the basis emulator and equal periods
  big <- random_grid_data(n = 401, runs = 3)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", big), "additive")
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "separable", big), "product")
  bills <- random_grid_data(n = 401, runs = 3, days = TRUE)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", bills), "product")
  expect_error(bayesbem:::choose_discrepancy_kernel("additive", "separable", d),
               class = "bayesbem_error_argument")
  periods <- random_grid_data(n = 9, runs = 8, extra = 2, days = TRUE)
  expect_error(bayesbem:::choose_discrepancy_kernel("additive", "basis", periods),
               class = "bayesbem_error_argument")
  expect_snapshot(calibrate(d, emulator = "separable", discrepancy_kernel = "additive"), error = TRUE)
})

test_that("AR(1) noise needs the additive discrepancy and the rows' times", {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  choose <- bayesbem:::choose_noise_correlation
  expect_identical(choose("auto", "additive", d), "none")
  expect_identical(choose("none", "additive", d), "none")
  expect_error(choose("ar1", "product", d), class = "bayesbem_error_argument")
  # the rows' times are read where the spec finds the noise's segments, before sampling
  expect_error(bayesbem:::output_segments(d), class = "bayesbem_error_argument")
  expect_snapshot(calibrate(d, emulator = "basis", discrepancy_kernel = "additive",
                            noise_correlation = "ar1"), error = TRUE)
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * 0:8
  d$names$period <- "time"
  expect_identical(choose("ar1", "additive", d), "ar1")
  # "auto": AR(1) where it applies, on consecutive hours with the additive
  # discrepancy; not with the exact one, nor on rows none of which follow
  # another
  expect_identical(choose("auto", "additive", d), "ar1")
  expect_identical(choose("auto", "product", d), "none")
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * c(0, 2, 5, 9, 14, 20, 27, 35, 44)
  expect_identical(choose("auto", "additive", d), "none")
})
