test_that("the basis holds the runs: mean, components and truncated rest", {
  withr::local_seed(4)
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  basis <- bayesbem:::basis_emulator(d, variance = 0.9)
  e <- bayesbem:::grid_runs(d)[1:9, ]
  expect_equal(basis$mu, rowMeans(e))
  truncated <- e - basis$mu - basis$B %*% t(basis$w)
  expect_equal(basis$s2r, mean(truncated^2))
  # the fewest components that hold 90 % of the centred runs' variance
  d2 <- svd(e - rowMeans(e))$d^2
  pc <- ncol(basis$B)
  expect_gte(sum(d2[seq_len(pc)]) / sum(d2), 0.9)
  expect_lt(sum(d2[seq_len(pc - 1)]) / sum(d2), 0.9)
  # weights of unit variance over the runs, uncorrelated
  expect_equal(crossprod(basis$w) / nrow(basis$w), diag(pc))
  expect_length(basis$components, pc)
  # every component kept: nothing truncated
  full <- bayesbem:::basis_emulator(d, variance = 1)
  expect_equal(unname(full$mu + full$B %*% t(full$w)), unname(e))
  expect_lt(full$s2r, 1e-20)
})

test_that("a component's Gaussian process is at its marginal likelihood's maximum", {
  withr::local_seed(5)
  tc <- matrix(runif(24), 12, 2)
  w <- sin(3 * tc[, 1]) + tc[, 2]^2 + rnorm(12, sd = 0.01)
  gp <- bayesbem:::fit_component(tc, w)
  h <- cbind(1, tc)
  theta <- c(log(gp$beta), log(gp$s2), log(gp$nug))
  cov_at <- function(th) {
    exp(th[3]) * (exp(-exp(th[1]) * outer(tc[, 1], tc[, 1], "-")^2 -
                        exp(th[2]) * outer(tc[, 2], tc[, 2], "-")^2) + diag(exp(th[4]), 12))
  }
  # minus the profile log likelihood less n log(2 pi) / 2, by solve() and determinant()
  deviance <- function(th) {
    cov <- cov_at(th)
    b <- solve(t(h) %*% solve(cov, h), t(h) %*% solve(cov, w))
    r <- w - h %*% b
    0.5 * sum(r * solve(cov, r)) + 0.5 * determinant(cov)$modulus[[1]]
  }
  gls <- bayesbem:::component_gls(chol(cov_at(theta)), h, w)
  expect_equal(gls$deviance, deviance(theta), tolerance = 1e-8)
  # no step of 0.05 in any log hyperparameter does better (bounds aside)
  inside <- theta > c(-5, -5, -6, -14) + 0.05 & theta < c(8, 8, 6, 0) - 0.05
  for (k in which(inside)) {
    step <- replace(numeric(4), k, 0.05)
    expect_gte(deviance(theta + step), deviance(theta) - 1e-6)
    expect_gte(deviance(theta - step), deviance(theta) - 1e-6)
  }
  # the predictions' pieces
  k_runs <- solve(gp$ki)
  expect_equal(gp$b, drop(solve(t(h) %*% gp$ki %*% h, t(h) %*% gp$ki %*% w)))
  expect_equal(gp$alpha, drop(solve(k_runs, w - h %*% gp$b)))
})

test_that("stage 2 of a basis fit has the log density of the basis emulator given the runs", {
  skip_on_cran()
  withr::local_seed(22)
  problems <- list(
    shipped = list(d = koh_data(seb_field, seb_sim), priors = koh_priors()),
    random = list(d = random_grid_data(n = 9, runs = 8, extra = 2),
                  priors = koh_priors(tf = list(k1 = prior_normal(1.5, 0.2)),
                                      rho_delta = c(1.5, 0.5))),
    # periods of different lengths: each row's noise variance grows with its days
    periods = list(d = random_grid_data(n = 9, runs = 8, extra = 2, days = TRUE),
                   priors = koh_priors(tf = list(k1 = prior_normal(1.5, 0.2))))
  )
  for (pr in problems) {
    d <- pr$d
    basis <- bayesbem:::basis_emulator(d, variance = 0.99)
    emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                     b = numeric(sum(bayesbem:::mean_selection(pr$priors, d$p, d$q))),
                     basis = basis)
    # tf sampled as tf_u, tf = g(tf_u) (linear_box_lp())
    q <- d$q
    sd <- bayesbem:::basis_stan_data(d, pr$priors, emulator)
    model <- koh_model_for(sd, "koh_basis")
    g <- bayesbem:::gp_geometry(d, structure = "grid", basis = basis)
    for (i in 1:3) {
      # the tails of g as well as its linear middle
      pars <- list(tf = as.array(c(0.001, 0.999, stats::runif(q))[sample(q + 2, q)]),
                   rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
                   lambda_delta = stats::rgamma(1, 10, 0.3), lambda_e = stats::rgamma(1, 10, 0.03),
                   gamma = as.array(stats::rnorm(sd$n_h)))
      ref <- reference_basis(sd, basis, pars)
      u <- bayesbem:::linear_box_inverse(pars$tf)
      stan_pars <- stage2_pars(c(list(tf_u = as.array(u)), pars[names(pars) != "tf"]))
      unconstrained <- bayesbem:::basis_z(stan_pars, sd)
      expect_equal(as.numeric(rstan::constrain_pars(model, unconstrained)$tf),
                   as.numeric(pars$tf), tolerance = 1e-10)
      # Stan samples tf_u in units of the multiplier it receives
      expect_equal(as.numeric(unconstrained[seq_len(q)]), as.numeric(u) / sd$tf_multiplier,
                   tolerance = 1e-10)
      # log g'(u), g'(u) = inv_logit(u / a) - inv_logit((u - 1) / a)
      a <- sd$tf_edge
      jacobian <- sum(log(stats::plogis(u / a) - stats::plogis((u - 1) / a)))
      expect_equal(basis_log_density(model, sd, stan_pars), ref$lp + jacobian, tolerance = 1e-8)
      # what validate_emulator() and identifiability() read for a basis fit
      draw <- as_draw_pars(c(pars, list(rho_eta = rep(0.5, d$p + d$q), lambda_eta = 1,
                                                   b = emulator$b)),
                                      pr$priors$nugget, sd)
      fm <- bayesbem:::runs_field(g, draw)
      expect_equal(fm$mean, ref$mean, tolerance = 1e-8)
      expect_equal(fm$cov, ref$cov, tolerance = 1e-8)
      # validate_emulator()'s intervals: the basis emulator's own
      pred <- bayesbem:::emulator_prediction(g, draw)
      expect_equal(pred$mean, ref$mean, tolerance = 1e-8)
      expect_equal(pred$var, ref$eta_var, tolerance = 1e-8)
      # the analytic gradient (normal_basis.hpp) against central differences
      grad <- rstan::grad_log_prob(model, unconstrained)
      numeric_grad <- vapply(seq_along(unconstrained), function(k) {
        e <- replace(numeric(length(unconstrained)), k, 1e-5)
        (rstan::log_prob(model, unconstrained + e) - rstan::log_prob(model, unconstrained - e)) / 2e-5
      }, numeric(1))
      expect_equal(as.numeric(grad), numeric_grad, tolerance = 1e-5)
    }
  }
})

test_that("starting values given for tf reach a basis fit's Stan program as tf_u", {
  inits <- bayesbem:::basis_inits(list(list(tf = c(0.001, 0.2, 0.9, 0.999), lambda_e = 5),
                                       list(lambda_e = 3)))
  expect_named(inits[[1]], c("lambda_e", "tf_u"))
  u <- inits[[1]]$tf_u
  # g(u) = a (log(1 + e^(u / a)) - log(1 + e^((u - 1) / a))), a the edge
  # koh_basis.stan receives
  a <- bayesbem:::linear_box$edge
  expect_equal(as.numeric(a * (log1p(exp(u / a)) - log1p(exp((u - 1) / a)))),
               c(0.001, 0.2, 0.9, 0.999))
  # linear inside: u - g(u) ~ a (e^(-(1 - u) / a) - e^(-u / a))
  tf <- c(0.2, 0.9)
  expect_equal(as.numeric(u[2:3]) - tf, a * (exp(-(1 - tf) / a) - exp(-tf / a)),
               tolerance = 0.1)
  expect_equal(inits[[2]], list(lambda_e = 3))
  expect_equal(bayesbem:::basis_inits("random"), "random")
})

test_that("the basis emulator needs a modular fit, and \"auto\" picks it above 36 rows", {
  withr::local_options(cli.num_colors = 1)
  d12 <- koh_data(seb_field, seb_sim)
  choose <- bayesbem:::choose_emulator
  expect_equal(choose("auto", TRUE, d12), "separable")
  expect_equal(choose("auto", TRUE, list(n = 37L)), "basis")
  expect_equal(choose("basis", TRUE, d12), "basis")
  expect_equal(choose("auto", FALSE, d12), "none")
  expect_snapshot(calibrate(seb_field, seb_sim, modular = FALSE, emulator = "basis"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, emulator = "pca"), error = TRUE)
})

test_that("a basis fit of daily data converges near the truth", {
  skip_on_cran()
  problem <- bayesbem:::synthetic_problem(60, 15, 2)
  # the default iterations, 1000 to adapt the dense metric and 2000 draws:
  # with 500 + 500 R-hat was 1.01 or more for 2 of 6 seeds, with 1000 + 1000
  # for none
  fit <- suppressMessages(calibrate(problem$field, problem$runs, chains = 2, seed = test_seed(11),
                                    cores = 2, progress = FALSE))
  expect_equal(fit$settings$emulator, "basis")
  expect_equal(fit$settings[c("iter", "warmup")], list(iter = 3000L, warmup = 1000L))
  expect_equal(fit$settings$control, list(adapt_delta = 0.95, metric = "dense_e"))
  expect_equal(posterior::variables(posterior::subset_draws(fit$draws, variable = "tf_u")), sprintf("tf_u[%d]", 1:3))
  pc <- length(fit$emulator$basis$components)
  expect_gte(pc, 1)
  s <- summary(fit)
  expect_equal(s$basis$components, pc)
  expect_output(print(s), sprintf("basis emulator: %d component", pc))
  conv <- check_convergence(fit, warn = FALSE)
  expect_lt(max(conv$rhat), 1.01)
  # the truth within 2.5 posterior sds of the mean: a single fit's 90 %
  # intervals miss one of three parameters by chance one time in four (the
  # coverage rate is bench-reliability.R's to measure)
  draws <- bayesbem:::parameter_draws(fit)
  for (v in names(problem$truth)) {
    expect_lt(abs(mean(draws[, v]) - problem$truth[[v]]), 2.5 * stats::sd(draws[, v]))
  }
  # validate_emulator() reads the basis emulator the calibration used
  check <- validate_emulator(fit, problem$simulator, ndraws = 3)
  basis <- fit$emulator$basis
  par <- bayesbem:::draw_parameters(fit, 3)[[2]]
  wv <- bayesbem:::basis_weights(basis, par$tf)
  rows <- check$table$draw == attr(bayesbem:::draw_parameters(fit, 3), "index")[2]
  sc <- fit$data$scaling
  expect_equal(check$table$mean[rows], basis$mu * sc$y_scale + sc$y_center +
                 drop(basis$B %*% wv$mean) * sc$y_scale)
  expect_equal(check$table$sd[rows], sqrt(drop(basis$B^2 %*% wv$var) + basis$s2r) * sc$y_scale)
  expect_true(all(is.finite(check$shift$z)))
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

test_that("past its length scales' floor the additive discrepancy's density is rho's prior tail, finite", {
  skip_on_cran()
  withr::local_seed(24)
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  priors <- koh_priors(rho_delta = c(1, 0.3))
  basis <- bayesbem:::basis_emulator(d, variance = 0.99)
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                   b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))), basis = basis)
  sd <- bayesbem:::basis_stan_data(d, priors, emulator, bayesbem:::hsgp_design(m = 6, boundary = 3))
  model <- koh_model_for(sd, "koh_basis")
  pars <- stage2_pars(list(tf_u = as.array(bayesbem:::linear_box_inverse(rep(0.5, d$q))),
                           rho_delta = as.array(rep(0.5, sd$p)), lambda_delta = 30, lambda_e = 300,
                           gamma = as.array(numeric(sd$n_h))))
  u <- as.numeric(sd$u_offset) + drop(sd$u_scale %*% as.numeric(bayesbem:::basis_z(pars, sd)))
  # z where input 1's logit(rho_delta) is x: at x = 40, rho rounds to 1
  z_at <- function(x) drop(solve(sd$u_scale, replace(u, d$q + 1, x) - as.numeric(sd$u_offset)))
  lp <- vapply(c(30, 40), function(x) rstan::log_prob(model, z_at(x)), numeric(1))
  expect_true(all(is.finite(lp)))
  expect_true(all(is.finite(rstan::grad_log_prob(model, z_at(40)))))
  # the likelihood no longer moves (beta_delta ~ 4 e^-x under the floor 0.08), and
  # Beta(1, b)'s density in x falls as b log(1 - inv_logit(x)) ~ -b x
  expect_equal(lp[2] - lp[1], -10 * 0.3, tolerance = 1e-6)
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
