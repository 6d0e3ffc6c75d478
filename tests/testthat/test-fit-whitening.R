# Stage 2 of the modular fit samples z, with u = u_loc + u_scale z: any
# whitening is the same posterior, so Stan's log density at z equals the
# unwhitened one at u, and the constrained values are the same.
test_that("a whitening leaves stage 2's log density and parameters unchanged", {
  skip_on_cran()
  withr::local_seed(31)
  d <- random_grid_data(extra = 2)
  priors <- koh_priors()
  dense_sd <- bayesbem:::koh_stan_data(d, priors, structure = "dense")
  pars <- random_koh_pars(dense_sd)
  emulator <- list(beta_eta = -4 * log(pars$rho_eta), lambda_eta = pars$lambda_eta, b = pars$b)
  unit <- bayesbem:::modular_stan_data(d, priors, emulator)
  k <- length(unit$u_loc)
  expect_equal(k, unit$q + unit$p + 2 + unit$n_h)
  loc <- rnorm(k)
  scale <- matrix(rnorm(k * k, sd = 0.3), k) + diag(k)
  whitened <- modifyList(unit, list(u_loc = loc, u_scale = scale))
  plain <- koh_model_for(unit, "koh_modular")
  model <- koh_model_for(whitened, "koh_modular")
  u <- bayesbem:::stage2_unconstrain(pars, unit)
  z <- solve(scale, u - loc)
  expect_equal(rstan::log_prob(model, z), rstan::log_prob(plain, u), tolerance = 1e-10)
  values <- rstan::constrain_pars(model, z)
  for (par in c("tf", "rho_delta", "lambda_delta", "lambda_e")) {
    expect_equal(as.numeric(values[[par]]), as.numeric(pars[[par]]), tolerance = 1e-10)
  }
  expect_equal(as.numeric(values$u), u, tolerance = 1e-10)
})

test_that("stage2_unconstrain() applies Stan's transforms in the program's order", {
  sd <- list(q = 2L, p = 1L, n_h = 1L)
  values <- list(tf = c(0.2, 0.9), rho_delta = 0.5, lambda_delta = 4, lambda_e = 100,
                 gamma = -1.5)
  expect_equal(bayesbem:::stage2_unconstrain(values, sd),
               c(log(0.2 / 0.8), log(0.9 / 0.1), 0, log(4), log(100), -1.5))
  expect_equal(bayesbem:::stage2_unconstrain(values["tf"], sd),
               c(log(0.2 / 0.8), log(0.9 / 0.1), NA, NA, NA, NA))
})

test_that("stage2_starts() reads init and init_r as rstan::sampling() does", {
  sd <- list(q = 2L, p = 1L, n_h = 0L)
  random <- bayesbem:::stage2_starts(NULL, NULL, 3, 7, sd)
  expect_length(random, 3)
  expect_true(all(vapply(random, function(u) length(u) == 5 && all(abs(u) < 2), logical(1))))
  expect_identical(bayesbem:::stage2_starts("random", 2, 3, 7, sd), random)
  expect_false(isTRUE(all.equal(random[[1]], random[[2]])))
  narrow <- bayesbem:::stage2_starts(NULL, 0.5, 3, 7, sd)
  expect_equal(narrow[[2]], random[[2]] / 4)
  expect_equal(bayesbem:::stage2_starts(0, NULL, 2, 7, sd), list(numeric(5), numeric(5)))
  expect_equal(bayesbem:::stage2_starts("0", NULL, 1, 7, sd), list(numeric(5)))
  given <- list(list(tf = c(0.5, 0.5), rho_delta = 0.5, lambda_delta = 1, lambda_e = 1),
                list(tf = c(0.5, 0.5)))
  from_list <- bayesbem:::stage2_starts(given, NULL, 2, 7, sd)
  expect_equal(from_list[[1]], numeric(5))
  # what an init leaves out is drawn at random, as rstan does
  expect_equal(from_list[[2]], c(0, 0, random[[2]][3:5]))
  from_fun <- bayesbem:::stage2_starts(function(chain_id) list(tf = c(chain_id, 1) / 4), NULL, 2,
                                       7, sd)
  expect_equal(from_fun[[2]][1:2], qlogis(c(0.5, 0.25)))
  expect_equal(bayesbem:::stage2_starts(function() list(lambda_e = exp(2)), NULL, 1, 7,
                                        sd)[[1]][5], 2)
})

test_that("laplace_scale() is a square root of the inverse curvature", {
  A <- matrix(c(4, 1, 0.5, 1, 3, 0.2, 0.5, 0.2, 2), 3)
  S <- bayesbem:::laplace_scale(-A)
  expect_equal(S %*% t(S), solve(A), tolerance = 1e-10)
  # flat and saddle directions get at most sd 5
  S <- bayesbem:::laplace_scale(-diag(c(4, 0, -1)))
  expect_equal(S %*% t(S), diag(c(1 / 4, 25, 25)), tolerance = 1e-10)
})

# On the shipped case study's stage 2 (n = 12) the whitening's centre is a
# mode (gradient zero), its scale the inverse of the curvature there by
# finite differences of the log density (not of its gradient), and each
# chain's init maps back to the mode its own search reached.
test_that("whiten_stage2() centres on the best mode and scales by its curvature", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  priors <- koh_priors()
  median_of <- function(par) apply(as.matrix(seb_fit$stanfit, pars = par), 2, median)
  fixed <- list(beta_eta = median_of("beta_eta"), lambda_eta = median_of("lambda_eta"),
                b = median_of("b"))
  sd <- bayesbem:::modular_stan_data(d, priors, fixed)
  starts <- bayesbem:::stage2_starts(NULL, NULL, 3, 11, sd)
  w <- bayesbem:::whiten_stage2(bayesbem:::stanmodels$koh_modular, sd, starts)
  plain <- koh_model_for(sd, "koh_modular")
  m <- w$data$u_loc
  expect_lt(max(abs(rstan::grad_log_prob(plain, m))), 1e-3)
  k <- length(m)
  h <- 1e-3
  lp <- function(u) rstan::log_prob(plain, u)
  H <- outer(seq_len(k), seq_len(k), Vectorize(function(i, j) {
    ei <- replace(numeric(k), i, h)
    ej <- replace(numeric(k), j, h)
    (lp(m + ei + ej) - lp(m + ei - ej) - lp(m - ei + ej) + lp(m - ei - ej)) / (4 * h^2)
  }))
  S <- w$data$u_scale
  expect_equal(S %*% t(S), solve(-H), tolerance = 1e-3)
  best <- vapply(w$inits, function(init) max(abs(init$z)), numeric(1))
  expect_equal(min(best), 0)
  for (init in w$inits) {
    u <- m + drop(S %*% init$z)
    expect_lt(max(abs(rstan::grad_log_prob(plain, u))), 1e-3)
  }
})
