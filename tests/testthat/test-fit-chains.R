test_that("chains run one per process give rstan's own multi-chain draws", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  stan_data <- bayesbem:::koh_stan_data(d, koh_priors(), NULL, "grid")
  reference <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh, data = stan_data, chains = 2, iter = 150,
                    seed = test_seed(5), refresh = 0, control = list(adapt_delta = 0.9), cores = 1)
  )
  fit <- suppressWarnings(calibrate(d, chains = 2, iter = 150, seed = test_seed(5), cores = 2,
                                    control = list(adapt_delta = 0.9), minor_modes = "keep",
                                    modular = FALSE),
                          classes = "bayesbem_warning_convergence")
  expect_equal(unname(unclass(fit$draws)), unname(as.array(reference)))
  # the chains' draws as minor_mode_chains() reads them
  single <- lapply(1:2, function(k) {
    suppressWarnings(rstan::sampling(bayesbem:::stanmodels$koh, data = stan_data, chains = 1,
                                     chain_id = k, iter = 150, seed = test_seed(5), refresh = 0,
                                     control = list(adapt_delta = 0.9)))
  })
  expect_equal(unname(bayesbem:::chain_draws(single)), unname(as.array(reference)))
})

# Draws of four chains (iterations x chains x variables) from Gaussian
# modes: unconstrained b[1..6] with sd `spread`, lp__ around `height`.
mode_draws <- function(height, spread) {
  draws <- array(0, c(400, 4, 8), list(NULL, NULL, c(sprintf("b[%d]", 1:6), "beta_eta[1]", "lp__")))
  for (k in 1:4) {
    z <- withr::with_seed(k, matrix(stats::rnorm(400 * 6), 400))
    draws[, k, 1:6] <- z * spread[k]
    # the Gaussian log density up to its constant: height at the peak
    draws[, k, "lp__"] <- height[k] - rowSums(z^2) / 2
    draws[, k, "beta_eta[1]"] <- 3
  }
  draws
}

test_that("chains stuck in a mode of far lower posterior mass are found", {
  none <- list(drop = integer(0), restart = integer(0), from = NULL)
  # log mass = height + 6 log(spread): chain 3's mode has e^-30 of the
  # first chains' mass; chain 4's peak is 12 lower but 10 times wider in 6
  # directions (log mass -12 + 13.8 = 1.8 against the first chains')
  draws <- mode_draws(height = c(0, 0.5, -30, -12), spread = c(1, 1, 1, 10))
  expect_equal(bayesbem:::minor_mode_chains(draws), list(drop = 3L, restart = integer(0), from = NULL))
  # modes of similar mass are kept: the chains disagree, and R-hat says so
  expect_equal(bayesbem:::minor_mode_chains(mode_draws(c(0, 0, -3, 0), rep(1, 4))), none)
  # the main mode found by one chain: the others start again from it, unless
  # it had divergent transitions
  lone <- mode_draws(c(0, -30, -30, -30), rep(1, 4))
  expect_equal(bayesbem:::minor_mode_chains(lone), list(drop = integer(0), restart = 2:4, from = 1L))
  expect_equal(bayesbem:::minor_mode_chains(lone, divergent = c(1, 0, 0, 0)), none)
  # one chain, or too few draws for a covariance: nothing is judged
  expect_equal(bayesbem:::minor_mode_chains(draws[, 1, , drop = FALSE]), none)
  expect_equal(bayesbem:::minor_mode_chains(draws[1:4, , ]), none)
})

# mode_draws() with two calibration parameters in front: tf[1] around 0.5
# and tf[2] around 0.3 in every chain but those in `elsewhere`, whose tf[1]
# sits around 0.9.
tf_mode_draws <- function(height, elsewhere = integer(0)) {
  d <- mode_draws(height, rep(1, 4))
  out <- array(0, dim(d) + c(0, 0, 2), list(NULL, NULL, c("tf[1]", "tf[2]", dimnames(d)[[3]])))
  out[, , -(1:2)] <- d
  for (k in 1:4) {
    z <- withr::with_seed(10 + k, matrix(stats::rnorm(800, sd = 0.2), 400))
    out[, k, "tf[1]"] <- stats::plogis(stats::qlogis(if (k %in% elsewhere) 0.9 else 0.5) + z[, 1])
    out[, k, "tf[2]"] <- stats::plogis(stats::qlogis(0.3) + z[, 2])
  }
  out
}

test_that("a stage-2 minor mode that puts the calibration elsewhere is kept", {
  draws <- tf_mode_draws(c(0, 0.5, -30, 0.2), elsewhere = 3L)
  # where the minor chain put the calibration, against the other chains
  minor_tf <- bayesbem:::minor_mode_tf(draws, 3L)
  expect_equal(minor_tf["median", ], c(`tf[1]` = median(draws[, 3, "tf[1]"]),
                                      `tf[2]` = median(draws[, 3, "tf[2]"])))
  expect_equal(minor_tf[c("lower", "upper"), "tf[1]"],
               c(lower = unname(quantile(draws[, -3, "tf[1]"], 0.05)),
                 upper = unname(quantile(draws[, -3, "tf[1]"], 0.95))))
  expect_equal(bayesbem:::moved_tf(minor_tf), c(`tf[1]` = TRUE, `tf[2]` = FALSE))
  # a joint fit (or stage 1) drops it; stage 2 keeps it
  joint <- bayesbem:::settle_minor_modes(draws, integer(4))
  expect_equal(joint[c("drop", "restart", "kept")],
               list(drop = 3L, restart = integer(0), kept = integer(0)))
  expect_equal(joint$minor_tf, minor_tf)
  stage2 <- bayesbem:::settle_minor_modes(draws, integer(4), keep_moved = TRUE)
  expect_equal(stage2[c("drop", "restart", "kept")],
               list(drop = integer(0), restart = integer(0), kept = 3L))
  # a minor mode with the calibration in place is dropped in stage 2 too
  same <- tf_mode_draws(c(0, 0.5, -30, 0.2))
  expect_equal(bayesbem:::settle_minor_modes(same, integer(4), keep_moved = TRUE)$drop, 3L)
  # chains that would have been restarted from a lone chain are kept
  lone <- bayesbem:::settle_minor_modes(tf_mode_draws(c(0, -30, -30, -30), elsewhere = 2:4),
                                        integer(4), keep_moved = TRUE)
  expect_equal(lone[c("drop", "restart", "kept")],
               list(drop = integer(0), restart = integer(0), kept = 2:4))
  expect_null(lone$from)
  # no minor chain, or no calibration parameter: nothing to place
  expect_null(bayesbem:::minor_mode_tf(draws, integer(0)))
  expect_null(bayesbem:::minor_mode_tf(draws[, , -(1:2)], 3L))
  expect_identical(bayesbem:::moved_tf(NULL), logical(0))
})

test_that("chains kept in a minor mode are reported in the message, summary and hint", {
  skip_on_cran()
  withr::local_options(cli.num_colors = 1)
  # stage 2 keeps chain 2, whose mode put every calibration parameter at the
  # bottom of its range
  settle <- bayesbem:::settle_minor_modes
  utils::assignInNamespace("settle_minor_modes", function(draws, divergent, keep_moved = FALSE) {
    tf <- grep("^tf\\[", dimnames(draws)[[3]], value = TRUE)
    list(drop = integer(0), restart = integer(0), from = NULL,
         kept = if (keep_moved) 2L else integer(0),
         minor_tf = if (keep_moved) rbind(median = rep(0.001, length(tf)), lower = 0.4, upper = 0.6))
  }, "bayesbem")
  withr::defer(utils::assignInNamespace("settle_minor_modes", settle, "bayesbem"))
  messages <- list()
  w <- expect_warning(
    withCallingHandlers(
      fit <- calibrate(seb_field, seb_sim, chains = 2, iter = 150, seed = test_seed(5), cores = 2,
                       modular = TRUE, control = list(adapt_delta = 0.9)),
      bayesbem_message_minor_modes = function(m) {
        messages[[length(messages) + 1L]] <<- conditionMessage(m)
        invokeRestart("muffleMessage")
      }),
    class = "bayesbem_warning_convergence")
  expect_length(messages, 1)
  expect_match(messages[[1]], "Chain 2 was kept in a minor mode .* elsewhere:")
  low <- bayesbem:::unscale_t1(0.001, fit$data$scaling, 1)
  expect_match(messages[[1]], sprintf("%s: %s in the minor mode", fit$data$names$t[1], signif(low, 3)),
               fixed = TRUE)
  expect_equal(fit$settings$kept_moved, 2L)
  expect_equal(posterior::nchains(fit$draws), 2L)
  expect_match(conditionMessage(w), "Chain 2 was kept in a minor mode")
  expect_match(capture.output(print(summary(fit)))[2], "kept (minor mode): chain 2 (calibration elsewhere)",
               fixed = TRUE)
})

test_that("restarted chains start from the main mode's draws and are reported", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  sample_seb <- function(chain_id, ...) {
    suppressWarnings(rstan::sampling(bayesbem:::stanmodels$koh,
                                     data = bayesbem:::koh_stan_data(d, koh_priors(), NULL, "grid"),
                                     chains = 1, chain_id = chain_id, iter = 150, seed = test_seed(5),
                                     refresh = 0, control = list(adapt_delta = 0.9), ...))
  }
  first <- sample_seb(1)
  inits <- bayesbem:::restart_inits(first, 2)
  draws <- as.array(first)[, 1, ]
  # every parameter of the program, those the grid likelihood does not sample with no elements
  expect_named(inits[[2]], c("tf", "rho_eta", "rho_delta", "lambda_eta", "lambda_delta",
                             "lambda_e", "gamma", "b", "y_pred"))
  expect_length(inits[[2]]$y_pred, 0L)
  expect_equal(inits[[2]]$tf, array(unname(draws[75, sprintf("tf[%d]", 1:3)]), 3))
  expect_equal(inits[[1]]$lambda_e, array(unname(draws[38, "lambda_e[1]"]), 1))
  # the judgement made to restart chain 2 from chain 1 (it is tested above)
  judge <- bayesbem:::minor_mode_chains
  utils::assignInNamespace("minor_mode_chains", function(draws, divergent) {
    list(drop = integer(0), restart = 2L, from = 1L)
  }, "bayesbem")
  withr::defer(utils::assignInNamespace("minor_mode_chains", judge, "bayesbem"))
  expect_message(
    fit <- suppressWarnings(calibrate(d, chains = 2, iter = 150, seed = test_seed(5), cores = 2,
                                      control = list(adapt_delta = 0.9), modular = FALSE),
                            classes = "bayesbem_warning_convergence"),
    "Chain 2 was stuck in a minor mode .* run again from the draws of chain 1",
    class = "bayesbem_message_minor_modes"
  )
  expect_equal(fit$settings$restarted, list(chains = 2L, from = 1L))
  drawn <- unname(unclass(fit$draws))
  expect_equal(drawn[, 1, ], unname(as.array(first)[, 1, ]))
  expect_equal(drawn[, 2, ],
               unname(as.array(sample_seb(2, init = bayesbem:::restart_inits(first, 1)))[, 1, ]))
  expect_match(capture.output(print(summary(fit)))[2], "restarted (minor mode): chain 2 from chain 1",
               fixed = TRUE)
})

test_that("draws go to Stan's unconstrained scale, parameters block only", {
  draws <- cbind(`tf[1]` = c(0.2, 0.7), `rho_eta[2]` = c(0.5, 0.9), lambda_e = c(10, 400),
                 `b[1]` = c(-1, 2), `beta_eta[1]` = c(1, 2), lp__ = c(-3, -4))
  u <- bayesbem:::unconstrained_draws(draws)
  expect_equal(colnames(u), c("tf[1]", "rho_eta[2]", "lambda_e", "b[1]"))
  expect_equal(unname(u[, 1]), log(c(0.2, 0.7) / c(0.8, 0.3)))
  expect_equal(unname(u[, 2]), stats::qlogis(c(0.5, 0.9)))
  expect_equal(unname(u[, 3]), log(c(10, 400)))
  # koh_basis.stan samples tf_u; its tf is a transformed parameter
  u <- bayesbem:::unconstrained_draws(cbind(draws, `tf_u[1]` = c(-1, 3)))
  expect_equal(colnames(u), c("rho_eta[2]", "lambda_e", "b[1]", "tf_u[1]"))
  expect_equal(unname(u[, 4]), c(-1, 3))
  # where it samples z, z alone
  z <- bayesbem:::unconstrained_draws(cbind(draws, `tf_u[1]` = c(-1, 3), `z[1]` = c(0.1, 0.2)))
  expect_equal(colnames(z), "z[1]")
})

test_that("dropped and restarted chains are named in the message and the summary", {
  expect_message(bayesbem:::inform_minor_modes(c(1L, 4L)), class = "bayesbem_message_minor_modes")
  expect_silent(bayesbem:::inform_minor_modes())
  expect_snapshot(bayesbem:::inform_minor_modes(c(1L, 4L)))
  moved <- "fan_total_efficiency: 0.45 in the minor mode, 0.61 to 0.86 (90%) in the main mode."
  expect_snapshot(bayesbem:::inform_minor_modes(3L, moved = moved))
  expect_snapshot(bayesbem:::inform_minor_modes(integer(0), list(chains = 2:4, from = 1L), moved))
  expect_snapshot(bayesbem:::inform_minor_modes(moved = moved, kept = 2:3))
  expect_equal(bayesbem:::minor_modes_label(3L), "; dropped (minor mode): chain 3")
  expect_equal(bayesbem:::minor_modes_label(integer(0), list(chains = c(1L, 3L), from = 2L)),
               "; restarted (minor mode): chains 1, 3 from chain 2")
  expect_equal(bayesbem:::minor_modes_label(), "")
  expect_equal(bayesbem:::minor_modes_label(1L, kept = 2:3),
               "; dropped (minor mode): chain 1; kept (minor mode): chains 2, 3 (calibration elsewhere)")
})

test_that("the calibration parameters a minor mode put elsewhere are named", {
  tf <- bayesbem:::stan_draws(seb_fit, "tf")
  physical <- bayesbem:::parameter_draws(seb_fit)
  # the minor mode at the fit's medians, but the first parameter at the
  # bottom of its range, outside the fit's 90 % interval
  minor_tf <- rbind(median = apply(tf, 2, median), lower = apply(tf, 2, quantile, 0.05),
                    upper = apply(tf, 2, quantile, 0.95))
  expect_identical(bayesbem:::moved_parameters(seb_fit, minor_tf), character())
  minor_tf["median", 1] <- 0.001
  moved <- bayesbem:::moved_parameters(seb_fit, minor_tf)
  expect_length(moved, 1)
  low <- bayesbem:::unscale_t1(0.001, seb_fit$data$scaling, 1)
  expect_lt(low, quantile(physical[, 1], 0.05))
  expect_equal(moved, sprintf("%s: %s in the minor mode, %s to %s (90%%) in the main mode.",
                              colnames(physical)[1], signif(low, 3),
                              signif(quantile(physical[, 1], 0.05, names = FALSE), 3),
                              signif(quantile(physical[, 1], 0.95, names = FALSE), 3)))
  expect_identical(bayesbem:::moved_parameters(seb_fit, NULL), character())
})

test_that("rstan's diagnostic warnings are told by the function that raised them", {
  skip_on_cran()
  short <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh,
                    data = bayesbem:::koh_stan_data(koh_data(seb_field, seb_sim), koh_priors(),
                                                    NULL, "grid"),
                    chains = 2, iter = 30, seed = test_seed(1), refresh = 0)
  )
  told <- logical()
  withCallingHandlers({
    rstan:::throw_sampler_warnings(short)
    warning("something else")
  }, warning = function(w) {
    told[conditionMessage(w)] <<- bayesbem:::from_rstan_diagnostics()
    invokeRestart("muffleWarning")
  })
  expect_gt(length(told), 1)
  expect_true(all(told[names(told) != "something else"]))
  expect_false(told[["something else"]])
})

test_that("progress is read from Stan's iteration lines", {
  logs <- c(tempfile(), tempfile(), tempfile())
  writeLines(c("Chain 1: Iteration:   1 / 400 [  0%]  (Warmup)",
               "Chain 1: Iteration: 120 / 400 [ 30%]  (Warmup)"), logs[1])
  writeLines(c("Chain 2: Iteration: 400 / 400 [100%]  (Sampling)", "Chain 2: ",
               "Chain 2:  Elapsed Time: 0.1 seconds (Warm-up)"), logs[2])
  expect_equal(bayesbem:::chain_progress(logs, 400), c(120, 400, 0))
})

test_that("a chain whose process fails is a classed error", {
  results <- list(list(fit = NULL, warnings = list()), bayesbem:::try_error("out of memory"))
  expect_error(bayesbem:::collect_chains(results, 3:4, identity, NULL),
               "Chain 4 failed.*out of memory", class = "bayesbem_error_sampling")
})

test_that("a list of starting values gives each chain its own", {
  skip_on_cran()
  starts <- list(list(tf = c(0.2, 0.2, 0.2)), list(tf = c(0.8, 0.8, 0.8)))
  fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 2, iter = 20, seed = test_seed(1),
                                    init = starts),
                          classes = "bayesbem_warning_convergence")
  expect_equal(lapply(fit$inits, function(i) as.vector(i$tf)),
               list(rep(0.2, 3), rep(0.8, 3)))
})

# koh_basis.stan's data on 12 field rows (hourly, with `ar1`) and 8 runs:
# the emulator at unit hyperparameters, a small additive discrepancy.
small_basis_data <- function(ar1 = FALSE) {
  d <- random_grid_data(n = 12, runs = 8, extra = 2)
  if (ar1) {
    d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * (0:11)
    d$names$period <- "time"
  }
  priors <- koh_priors()
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                   b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))),
                   basis = bayesbem:::basis_emulator(d, variance = 0.99))
  list(d = d, sd = bayesbem:::basis_stan_data(d, priors, emulator,
                                              bayesbem:::hsgp_design(m = 6, boundary = 3),
                                              if (ar1) bayesbem:::output_segments(d)))
}

test_that("a chain started at the mode starts where the gradient vanishes, from its own start", {
  skip_on_cran()
  withr::local_seed(26)
  small <- small_basis_data()
  d <- small$d
  sd <- small$sd
  model <- bayesbem:::stanmodels$koh_basis
  starts <- lapply(1:2, function(chain) bayesbem:::mode_start(model, sd, 7, chain))
  instance <- koh_model_for(sd, "koh_basis")
  for (start in starts) {
    expect_length(start, 1)
    u <- rstan::unconstrain_pars(instance, start[[1]])
    # BFGS's mode: the gradient of the log density (Jacobian included) near 0
    expect_lt(max(abs(rstan::grad_log_prob(instance, u))), 1e-3)
    expect_true(is.array(start[[1]]$tf_u))
  }
  # the same seed and chain, the same start
  expect_equal(bayesbem:::mode_start(model, sd, 7, 1), starts[[1]])
})

test_that("koh_basis.stan samples through the Laplace approximation at a mode", {
  skip_on_cran()
  withr::local_seed(27)
  small <- small_basis_data(ar1 = TRUE)
  d <- small$d
  sd <- small$sd
  expect_equal(sd$n_u, d$q + d$p + 3)
  expect_equal(sd$u_scale, diag(sd$n_u))
  mapped <- bayesbem:::laplace_map(bayesbem:::stanmodels$koh_basis, sd, 5)
  identity <- koh_model_for(sd, "koh_basis")
  instance <- koh_model_for(mapped, "koh_basis")
  # the same density at z as the identity's at u = u_offset + u_scale z
  for (i in 1:3) {
    z <- stats::rnorm(sd$n_u)
    u <- as.numeric(mapped$u_offset) + drop(mapped$u_scale %*% z)
    expect_equal(rstan::log_prob(instance, z), rstan::log_prob(identity, u), tolerance = 1e-8)
  }
  # z = 0 is the mode, where the density's curvature in z is the unit
  # matrix (1 along directions of curvature 0.01 or more, less along flatter
  # ones), from the Hessian in u by central differences, independently
  expect_lt(max(abs(rstan::grad_log_prob(instance, numeric(sd$n_u)))), 1e-3)
  h_u <- -bayesbem:::log_prob_hessian(identity, mapped$u_offset)
  lambda <- eigen(h_u, symmetric = TRUE, only.values = TRUE)$values
  expected <- ifelse(lambda > 0, lambda / pmax(lambda, 0.01), lambda)
  h_z <- -bayesbem:::log_prob_hessian(instance, numeric(sd$n_u))
  expect_equal(h_z, diag(expected), tolerance = 1e-3)
  # starting values by name reach z and come back
  values <- list(tf_u = as.array(c(0.2, 0.5, 0.7)), rho_delta = as.array(rep(0.7, d$p)),
                 lambda_delta = as.array(30), lambda_e = as.array(200), gamma = numeric(0),
                 phi = as.array(0.6))
  back <- rstan::constrain_pars(instance, bayesbem:::basis_z(values, mapped))
  for (par in names(values)) expect_equal(as.numeric(back[[par]]), as.numeric(values[[par]]))
})

test_that("the Laplace map's search also starts from a small, smooth discrepancy", {
  skip_on_cran()
  withr::local_seed(28)
  small <- small_basis_data()
  d <- small$d
  sd <- small$sd
  instance <- koh_model_for(sd, "koh_basis")
  starts <- bayesbem:::basis_starts(instance, sd, 5)
  expect_equal(dim(starts), c(sd$n_u, 2 * bayesbem:::mode_starts))
  random <- starts[, seq_len(bayesbem:::mode_starts)]
  smooth <- starts[, -seq_len(bayesbem:::mode_starts)]
  expect_true(all(random >= -2 & random <= 2))
  # read back through Stan's own transforms: the discrepancy's length
  # scales long and its precision high, the rest as the random starts
  for (k in seq_len(ncol(smooth))) {
    at_smooth <- rstan::constrain_pars(instance, smooth[, k])
    at_random <- rstan::constrain_pars(instance, random[, k])
    expect_equal(as.numeric(at_smooth$rho_delta), rep(stats::plogis(3), d$p))
    expect_equal(as.numeric(at_smooth$lambda_delta), exp(3))
    for (par in c("tf", "lambda_e")) expect_equal(at_smooth[[par]], at_random[[par]])
  }
})
