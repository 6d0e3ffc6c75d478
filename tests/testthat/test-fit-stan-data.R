# The Stan data lists, checked against the data and the priors directly,
# without sampling.

test_that("the dense likelihood's data are the scaled data, with no predictions by default", {
  d <- koh_data(seb_field, seb_sim)
  sd <- bayesbem:::koh_stan_data(d, koh_priors())
  expect_equal(sd$likelihood, 1L)
  expect_equal(c(sd$n, sd$mt, sd$p, sd$q, sd$K), c(12L, 120L, 3L, 3L, 1L))
  expect_equal(sd$y, d$y)
  expect_equal(sd$eta_c, d$eta)
  expect_equal(sd$tc, d$tc)
  expect_equal(sd$n_pred, 0L)
  # what the grid and stage-2 likelihoods read is there at size zero
  expect_equal(c(sd$n_x, sd$n_max), c(0L, 0L))
  expect_equal(dim(sd$eta), c(0L, 120L))
  expect_equal(dim(sd$E_f), c(0L, 120L))
  expect_equal(dim(sd$beta_eta_fixed), c(6L, 0L))
  expect_equal(as.vector(sd$output), rep(1, 12))
  # twelve calendar months weigh about one each (their days over the mean)
  expect_equal(sd$noise_weight, as.array(bayesbem:::noise_weights(d)))
  expect_equal(length(sd$noise_weight), 12L)
})

test_that("a normal prior goes to Stan on the design range's [0, 1] scale", {
  d <- koh_data(seb_field, seb_sim)
  name <- d$names$t[2]
  bounds <- bayesbem:::t_bounds(d$scaling)
  lo <- bounds$lower[[name]]
  hi <- bounds$upper[[name]]
  mu <- lo + 0.25 * (hi - lo)
  priors <- koh_priors(tf = stats::setNames(list(prior_normal(mu, 0.1)), name))
  p <- bayesbem:::koh_prior_data(d, priors)
  expect_equal(p$tf_is_normal, as.array(c(0, 1, 0)))
  expect_equal(p$tf_mu[2], 0.25)
  expect_equal(p$tf_sd[2], 0.1)
  expect_equal(as.vector(p$tf_v_lo + p$tf_v_span), unname(unlist(bounds$upper)))
  outside <- koh_priors(tf = stats::setNames(list(prior_normal(hi + 1, 0.1)), name))
  expect_error(bayesbem:::koh_prior_data(d, outside), "design range", class = "bayesbem_error_prior")
  unknown <- koh_priors(tf = list(no_such = prior_normal(1, 0.1)))
  expect_error(bayesbem:::koh_prior_data(d, unknown), "no_such", class = "bayesbem_error_prior")
})

test_that("the basis program's scale for tf is inverted exactly", {
  # g(u) = a (log(1 + e^(u / a)) - log(1 + e^((u - 1) / a))), linear_box_lp()
  a <- bayesbem:::linear_box$edge
  g <- function(u) a * (log1p(exp(u / a)) - log1p(exp((u - 1) / a)))
  tf <- c(0.001, 0.05, 0.3, 0.5, 0.9, 0.999)
  expect_equal(g(bayesbem:::linear_box_inverse(tf)), tf, tolerance = 1e-10)
  # away from the edges g is the identity to within about a e^(-d / a), d the
  # distance to the nearer edge
  inside <- c(0.3, 0.6)
  expect_true(all(abs(bayesbem:::linear_box_inverse(inside) - inside) <
                    2 * a * exp(-pmin(inside, 1 - inside) / a)))
})

test_that("starting values become the basis program's z by its transforms", {
  sd <- list(q = 2L, p = 1L, K = 1L, n_h = 0L, ar = 1L, tf_multiplier = 0.25,
             u_scale = diag(2, 6), u_offset = rep(1, 6))
  values <- list(tf_u = c(0.1, 0.2), rho_delta = 0.7, lambda_delta = 3, lambda_e = 50, phi = 0.5)
  u <- c(0.1 / 0.25, 0.2 / 0.25, stats::qlogis(0.7), log(3), log(50), stats::qlogis(0.75))
  expect_equal(as.vector(bayesbem:::basis_z(values, sd)), (u - 1) / 2)
  expect_equal(bayesbem:::basis_inits(list(list(tf = c(0.3, 0.6))))[[1]]$tf_u,
               as.array(bayesbem:::linear_box_inverse(c(0.3, 0.6))))
  expect_equal(bayesbem:::basis_inits("random"), "random")
})

test_that("stage 1 reads the grid's runs on a subset of its inputs, stage 2 the fixed emulators", {
  d <- koh_data(seb_field, seb_sim)
  priors <- koh_priors()
  grid <- bayesbem:::koh_stan_data(d, priors, structure = "grid")
  expect_equal(grid$likelihood, 2L)
  expect_equal(dim(grid$eta_f), c(12L, grid$mt))
  expect_equal(grid$eta_f, grid$eta[bayesbem:::field_rows(d$grid), ], ignore_attr = TRUE)
  stage1 <- bayesbem:::emulator_stan_data(d, priors)
  expect_equal(stage1$likelihood, 3L)
  rows <- bayesbem:::emulator_rows(d$grid)
  expect_equal(stage1$eta, grid$eta[rows, , drop = FALSE])
  expect_equal(dim(stage1$eta_f), c(0L, grid$mt))
  emulator <- list(beta_eta = seq(0.5, 3, length.out = 6), lambda_eta = 2, b = rep(0.1, grid$n_b))
  stage2 <- bayesbem:::modular_stan_data(d, priors, emulator)
  expect_equal(stage2$likelihood, 4L)
  expect_equal(as.vector(stage2$beta_eta_fixed), emulator$beta_eta)
  expect_equal(as.vector(stage2$lambda_eta_fixed), 2)
  expect_equal(dim(stage2$E_f), c(12L, grid$mt))
  # the Cholesky factor of the jittered run correlation, from the t part of beta_eta
  kt <- exp(-as.matrix(stats::dist(sweep(d$grid$design, 2, sqrt(emulator$beta_eta[4:6]), `*`)))^2) +
    priors$nugget * diag(grid$mt)
  expect_equal(stage2$Lt %*% t(stage2$Lt), kt, ignore_attr = TRUE, tolerance = 1e-10)
  # what the joint likelihoods read is there at size zero
  expect_equal(c(stage2$n_x, nrow(stage2$xc), nrow(stage2$eta_f)), c(0L, 0L, 0L))
})
