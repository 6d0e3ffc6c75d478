# The modular fit's two log densities add up to the joint grid density: the
# runs' density and the emulator priors (stage 1) plus the field outputs'
# density given the runs and the other priors (stage 2), at the same values.
test_that("stage 1 + stage 2 log densities equal the joint grid density", {
  skip_on_cran()
  withr::local_seed(21)
  problems <- list(
    shipped = list(d = koh_data(seb_field, seb_sim), priors = koh_priors()),
    random = list(d = random_grid_data(extra = 2),
                  priors = koh_priors(tf = list(k1 = prior_normal(1.5, 0.2)), nugget = 1e-4,
                                      emulator_mean = "constant", rho_eta = c(2, 0.3),
                                      rho_delta = c(1.5, 0.5)))
  )
  for (pr in problems) {
    d <- pr$d
    grid_sd <- bayesbem:::koh_stan_data(d, pr$priors, structure = "grid")
    dense_sd <- bayesbem:::koh_stan_data(d, pr$priors, structure = "dense")
    model_grid <- koh_model_for(grid_sd)
    # stage 1 on every grid input (the problems have fewer than 60)
    stage1_sd <- bayesbem:::emulator_stan_data(d, pr$priors)
    expect_equal(stage1_sd$eta, grid_sd$eta)
    model_stage1 <- koh_model_for(stage1_sd)
    for (i in 1:3) {
      pars <- random_koh_pars(dense_sd)
      emulator <- list(beta_eta = -4 * log(pars$rho_eta), lambda_eta = pars$lambda_eta,
                       b = pars$b)
      stage2_sd <- bayesbem:::modular_stan_data(d, pr$priors, emulator)
      model_stage2 <- koh_model_for(stage2_sd)
      lp1 <- stan_log_density(model_stage1, pars[c("rho_eta", "lambda_eta", "b")])
      lp2 <- stan_log_density(model_stage2, stage2_pars(pars))
      joint <- stan_log_density(model_grid, pars[names(pars) != "y_pred"])
      expect_equal(lp1 + lp2, joint, tolerance = 1e-8)
      expect_equal(lp1 + lp2, reference_log_density(dense_sd, pars), tolerance = 1e-8)
    }
  }
})

test_that("stage 1 uses at most 60 grid inputs, evenly spaced", {
  expect_equal(bayesbem:::emulator_rows(list(n_x = 12)), 1:12)
  rows <- bayesbem:::emulator_rows(list(n_x = 365))
  expect_length(rows, 60)
  expect_equal(range(rows), c(1, 365))
})

test_that("the modular fit needs a grid and says so", {
  withr::local_options(cli.num_colors = 1)
  expect_snapshot(calibrate(seb_field, seb_sim, structure = "dense", modular = TRUE), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, modular = "yes"), error = TRUE)
})

test_that("modular = \"auto\" fits in two stages on a grid design", {
  d12 <- koh_data(seb_field, seb_sim)
  choose <- function(d, structure = "grid") bayesbem:::choose_modular("auto", d, structure)
  expect_true(choose(d12))
  expect_false(choose(d12, "dense"))
  expect_false(bayesbem:::choose_modular(FALSE, d12, "grid"))
  expect_true(bayesbem:::choose_modular(TRUE, d12, "grid"))
})

# Stage 1: the emulator at the highest mode of its posterior on Stan's
# unconstrained scale, checked against finite differences of Stan's own log
# density there (gradient zero, curvature negative) and against every search.
test_that("stage 1 finds the posterior mode of the emulator's hyperparameters", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  priors <- koh_priors()
  emulator <- bayesbem:::fit_emulator(d, priors, seed = test_seed(3), on_failure = stop)
  expect_named(emulator, c("beta_eta", "lambda_eta", "b", "lp", "searches"))
  expect_length(emulator$beta_eta, 6)
  expect_length(emulator$b, 7)
  expect_length(emulator$searches, 16)
  expect_equal(emulator$lp, max(emulator$searches))
  # the same mode from the same seed
  expect_equal(bayesbem:::fit_emulator(d, priors, seed = test_seed(3), on_failure = stop), emulator)
  # the mode on the unconstrained scale: logit rho, log lambda, b
  model <- koh_model_for(bayesbem:::emulator_stan_data(d, priors))
  u <- c(stats::qlogis(exp(-emulator$beta_eta / 4)), log(emulator$lambda_eta), emulator$b)
  expect_equal(rstan::log_prob(model, u), emulator$lp, tolerance = 1e-8)
  h <- 1e-4
  steps <- diag(h, length(u))
  grad <- apply(steps, 2, function(e) (rstan::log_prob(model, u + e) - rstan::log_prob(model, u - e)) / (2 * h))
  expect_lt(max(abs(grad)), 1e-3)
  curvature <- apply(steps, 2, function(e) {
    (rstan::log_prob(model, u + e) - 2 * emulator$lp + rstan::log_prob(model, u - e)) / h^2
  })
  expect_true(all(curvature < 0))
  expect_equal(bayesbem:::emulator_searches_label(c(3, 1, 3.005, -Inf)), "2 of 4 searches reached it")
})

test_that("a modular fit reports its fixed emulator apart from the sampled parameters", {
  skip_on_cran()
  fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 2, iter = 300, seed = test_seed(8),
                                    cores = 2, control = list(adapt_delta = 0.9)),
                          classes = "bayesbem_warning_convergence")
  expect_true(fit$settings$modular)
  conv <- check_convergence(fit, warn = FALSE)
  expect_false(any(conv$variable %in% attr(conv, "emulator")))
  expect_true(all(c("equipment_power_density", "lambda_delta", "lambda_e") %in% conv$variable))
  expect_false(anyNA(conv$rhat))
  s <- summary(fit)
  expect_equal(s$emulator["lambda_eta", "value"], fit$emulator$lambda_eta)
  expect_setequal(rownames(s$emulator), attr(conv, "emulator"))
  expect_setequal(rownames(s$hyperparameters),
                  c(sprintf("beta_delta[%s]", c("temp", "rh", "solar")), "lambda_delta", "lambda_e"))
  out <- capture.output(print(s))
  expect_true(any(grepl(paste0("^Emulator \\(standardised scale\\), fixed at its posterior mode given ",
                               "the runs \\(stage 1, [0-9]+ of 16 searches reached it\\):$"), out)))
})

test_that("modular and joint fits agree where the runs determine the emulator", {
  skip_on_cran()
  # a smooth simulator, well covered by 20 runs: the field data cannot teach
  # the emulator anything, so cutting their feedback changes nothing
  lin <- simulator(function(params, x) params$a * x$temp + params$b * sqrt(x$temp + 5),
                   x = data.frame(temp = seq(-5, 25, length.out = 10)),
                   parameters = data.frame(parameter = c("a", "b"), initial = c(1, 1),
                                           min = c(0, 0), max = c(2, 4)))
  field <- simulate_field(lin, list(a = 1.2, b = 2.5), noise_sd = 0.3, seed = 3)
  runs <- simulate_design(lin, design_lhs(lin$parameters, n = 20, seed = 4))
  fits <- lapply(c(joint = FALSE, modular = TRUE), function(modular) {
    suppressWarnings(calibrate(field, runs, chains = 2, iter = 1000, seed = test_seed(5), cores = 2,
                               modular = modular),
                     classes = "bayesbem_warning_convergence")
  })
  draws <- lapply(fits, bayesbem:::parameter_draws)
  for (p in c("a", "b")) {
    sd_joint <- sd(draws$joint[, p])
    expect_lt(abs(mean(draws$modular[, p]) - mean(draws$joint[, p])), 0.3 * sd_joint)
    expect_equal(sd(draws$modular[, p]), sd_joint, tolerance = 0.3)
  }
  # the fixed emulator is reported from its stage-1 chains, and the fit predicts
  conv <- check_convergence(fits$modular, warn = FALSE)
  expect_false(anyNA(conv$rhat))
  expect_output(print(fits$modular), "modular")
  p <- predict(fits$modular, ndraws = 50)
  expect_lt(max(abs(p$mean - field$y)), 1)
})
