test_that("the Stan log density equals the method's, computed independently in R", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  priors <- koh_priors(tf = prior_level("weak", c(equipment_power_density = 20,
                                                  infiltration_per_exterior_area = 0.0008)))
  sd <- bayesbem:::koh_stan_data(d, priors)
  model <- koh_model_for(sd)
  withr::local_seed(42)
  for (i in 1:5) {
    pars <- random_koh_pars(sd)
    expect_equal(stan_log_density(model, pars), reference_log_density(sd, pars), tolerance = 1e-8)
  }
})

test_that("the Stan log density matches on other sizes, with outputs sampled in Stan", {
  skip_on_cran()
  withr::local_seed(7)
  n <- 5
  runs <- 6
  x <- matrix(runif(n * 2), n, 2, dimnames = list(NULL, c("a", "b")))
  design <- cbind(k1 = runif(runs, 0, 3), k2 = runif(runs, 10, 20), k3 = runif(runs))
  sim <- do.call(rbind, lapply(seq_len(runs), function(r) {
    data.frame(eta = rnorm(n, 5), x, t(design[r, ]))
  }))
  field <- data.frame(y = rnorm(n, 5), x)
  d <- koh_data(field, sim)
  sd <- bayesbem:::koh_stan_data(d, koh_priors(tf = list(k2 = prior_normal(12, 0.05)),
                                               nugget = 1e-4),
                                 x_pred = matrix(runif(4), 2, 2))
  model <- koh_model_for(sd)
  for (i in 1:3) {
    pars <- random_koh_pars(sd)
    expect_equal(stan_log_density(model, pars), reference_log_density(sd, pars), tolerance = 1e-8)
  }
})

# A random grid problem: every run at every field input and at `extra`
# further inputs, rows shuffled.
random_grid_data <- function(n = 7, runs = 5, extra = 2) {
  x <- matrix(runif((n + extra) * 2), n + extra, 2, dimnames = list(NULL, c("a", "b")))
  design <- cbind(k1 = runif(runs, 0, 3), k2 = runif(runs, 10, 20), k3 = runif(runs))
  sim <- do.call(rbind, lapply(seq_len(runs), function(r) {
    data.frame(eta = rnorm(n + extra, 5), x, t(design[r, ]))
  }))
  koh_data(data.frame(y = rnorm(n, 5), x[seq_len(n), ]), sim[sample(nrow(sim)), ])
}

test_that("the grid program's log density equals the dense program's", {
  skip_on_cran()
  withr::local_seed(11)
  # with two parametric discrepancy terms (extend())
  random <- bayesbem:::add_discrepancy_terms(random_grid_data(extra = 2),
                                             data.frame(w1 = rnorm(7), w2 = rep(0:1, c(3, 4))))
  k2_mid <- (random$scaling$t_min[["k2"]] + random$scaling$t_max[["k2"]]) / 2
  problems <- list(
    shipped = list(d = koh_data(seb_field, seb_sim),
                   priors = koh_priors(tf = prior_level("weak", c(equipment_power_density = 20)))),
    random = list(d = random, priors = koh_priors(tf = list(k2 = prior_normal(k2_mid, 0.05)),
                                                  nugget = 1e-4))
  )
  expect_equal(random$grid$n_x, 9)
  for (pr in problems) {
    dense <- bayesbem:::koh_stan_data(pr$d, pr$priors, structure = "dense")
    grid <- bayesbem:::koh_stan_data(pr$d, pr$priors, structure = "grid")
    model_dense <- koh_model_for(dense)
    model_grid <- koh_model_for(grid, "koh_grid")
    for (i in 1:4) {
      pars <- random_koh_pars(dense)
      lp_grid <- stan_log_density(model_grid, pars[names(pars) != "y_pred"])
      expect_equal(lp_grid, stan_log_density(model_dense, pars), tolerance = 1e-8)
      expect_equal(lp_grid, reference_log_density(dense, pars), tolerance = 1e-8)
    }
  }
})

test_that("a failing Cholesky factor is named, with the fix", {
  skip_on_cran()
  # months 1 and 2 at inputs 1e-10 apart: K_x is singular without a nugget
  x <- c("temp", "rh", "solar")
  index <- koh_data(seb_field, seb_sim)$grid$index
  field <- seb_field
  field[x] <- seb_sim[index[, 1], x]
  field[2, x] <- field[1, x] + c(1e-10, 0, 0)
  sim <- seb_sim
  sim[index, x] <- field[row(index), x]
  d <- koh_data(field, sim, grid_tol = 0)
  expect_false(is.null(d$grid))
  expect_error(calibrate(d, priors = koh_priors(nugget = 0), chains = 1, iter = 20, seed = 1,
                         refresh = 0),
               class = "bayesbem_error_cholesky")
  expect_snapshot(
    calibrate(d, priors = koh_priors(nugget = 0), chains = 1, iter = 20, seed = 1, refresh = 0),
    error = TRUE
  )
})

test_that("a small fit of the case study finds the equipment power density", {
  skip_on_cran()
  fit <- shared_fit()
  expect_s3_class(fit, "koh_fit")
  s <- summary(fit)
  epd <- s$parameters[s$parameters$variable == "equipment_power_density", ]
  expect_gt(epd$mean, 8)
  expect_lt(epd$mean, 17)
  expect_lt(epd$rhat, 1.05)
  # everything reported for tf is inside the design range, in physical units
  draws <- posterior::as_draws_df(fit)
  expect_true(all(draws$equipment_power_density >= min(seb_sim$equipment_power_density)))
  expect_true(all(draws$equipment_power_density <= max(seb_sim$equipment_power_density)))
})

test_that("print(), summary() and as_draws() show physical units and hyperparameters", {
  skip_on_cran()
  fit <- shared_fit()
  s <- summary(fit)
  expect_s3_class(s, "summary.koh_fit")
  expect_named(s$parameters, c("variable", "mean", "sd", "q5", "q50", "q95",
                               "rhat", "ess_bulk", "ess_tail"))
  expect_equal(s$parameters$variable, c("fan_total_efficiency", "equipment_power_density",
                                        "infiltration_per_exterior_area"))
  expect_setequal(s$hyperparameters$variable,
                  c("beta_eta[temp]", "beta_eta[rh]", "beta_eta[solar]",
                    "beta_eta[fan_total_efficiency]", "beta_eta[equipment_power_density]",
                    "beta_eta[infiltration_per_exterior_area]",
                    "beta_delta[temp]", "beta_delta[rh]", "beta_delta[solar]",
                    "lambda_eta", "lambda_delta", "lambda_e"))
  out <- capture.output(print(fit))
  expect_true(any(grepl("Calibration parameters (physical units)", out, fixed = TRUE)))
  expect_true(any(grepl("equipment_power_density", out)))
  expect_true(any(grepl("lambda_e", out)))
  draws <- posterior::as_draws(fit)
  expect_s3_class(draws, "draws_array")
  expect_equal(posterior::ndraws(draws), 1000)
  tf <- rstan::extract(fit$stanfit, "tf")$tf[, 2]
  lo <- min(seb_sim$equipment_power_density)
  hi <- max(seb_sim$equipment_power_density)
  expect_equal(sort(as.vector(posterior::as_draws_matrix(draws)[, "equipment_power_density"])),
               sort(tf * (hi - lo) + lo))
})

test_that("calibrate() rejects bad arguments with classed errors", {
  expect_error(calibrate(seb_field, seb_sim, chains = 2.5), class = "bayesbem_error_argument")
  expect_snapshot(calibrate(seb_field, seb_sim, chains = 0), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, iter = "500"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, iter = 100, warmup = 100), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, priors = list()), error = TRUE)
})
