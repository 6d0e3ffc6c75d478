test_that("chains run one per process give rstan's own multi-chain draws", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  stan_data <- bayesbem:::koh_stan_data(d, koh_priors(), NULL, "grid")
  reference <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh_grid, data = stan_data, chains = 2, iter = 150,
                    seed = 5, refresh = 0, control = list(adapt_delta = 0.9), cores = 1)
  )
  fit <- suppressWarnings(calibrate(d, chains = 2, iter = 150, seed = 5, cores = 2,
                                    control = list(adapt_delta = 0.9), minor_modes = "keep"),
                          classes = "bayesbem_warning_convergence")
  expect_equal(as.array(fit$stanfit), as.array(reference))
  # the chains' draws as minor_mode_chains() reads them
  single <- lapply(1:2, function(k) {
    suppressWarnings(rstan::sampling(bayesbem:::stanmodels$koh_grid, data = stan_data, chains = 1,
                                     chain_id = k, iter = 150, seed = 5, refresh = 0,
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

test_that("a chain stuck in a mode of far lower posterior mass is found", {
  # log mass = height + 6 log(spread): chain 3's mode has e^-30 of the
  # first chains' mass; chain 4's peak is 12 lower but 10 times wider in 6
  # directions (log mass -12 + 13.8 = 1.8 against the first chains')
  draws <- mode_draws(height = c(0, 0.5, -30, -12), spread = c(1, 1, 1, 10))
  expect_equal(bayesbem:::minor_mode_chains(draws), 3L)
  # modes of similar mass are kept: the chains disagree, and R-hat says so
  expect_equal(bayesbem:::minor_mode_chains(mode_draws(c(0, 0, -5, 0), rep(1, 4))), integer(0))
  # a single chain left to stand alone: nothing is dropped
  expect_equal(bayesbem:::minor_mode_chains(mode_draws(c(0, -30, -30, -30), rep(1, 4))),
               integer(0))
  # one chain, or too few draws for a covariance: nothing is judged
  expect_equal(bayesbem:::minor_mode_chains(draws[, 1, , drop = FALSE]), integer(0))
  expect_equal(bayesbem:::minor_mode_chains(draws[1:4, , ]), integer(0))
})

test_that("draws go to Stan's unconstrained scale, parameters block only", {
  draws <- cbind(`tf[1]` = c(0.2, 0.7), `rho_eta[2]` = c(0.5, 0.9), lambda_e = c(10, 400),
                 `b[1]` = c(-1, 2), `beta_eta[1]` = c(1, 2), lp__ = c(-3, -4))
  u <- bayesbem:::unconstrained_draws(draws)
  expect_equal(colnames(u), c("tf[1]", "rho_eta[2]", "lambda_e", "b[1]"))
  expect_equal(unname(u[, 1]), log(c(0.2, 0.7) / c(0.8, 0.3)))
  expect_equal(unname(u[, 3]), log(c(10, 400)))
})

test_that("dropped chains are named in the message and the summary", {
  expect_message(bayesbem:::inform_dropped(list(emulator = 2L, fit = c(1L, 4L))),
                 class = "bayesbem_message_minor_modes")
  expect_snapshot(bayesbem:::inform_dropped(list(emulator = 2L, fit = c(1L, 4L))))
  moved <- "fan_total_efficiency: 0.45 in the dropped chains, 0.61 to 0.86 (90%) in the kept ones."
  expect_snapshot(bayesbem:::inform_dropped(list(fit = 3L), moved))
  expect_equal(bayesbem:::dropped_label(list(emulator = 2L, fit = 3L)),
               "; dropped (minor mode): stage-1 chain 2; chain 3")
  expect_equal(bayesbem:::dropped_label(list()), "")
})

test_that("the calibration parameters a dropped chain put elsewhere are named", {
  tf <- as.matrix(seb_fit$stanfit, pars = "tf")
  physical <- bayesbem:::parameter_draws(seb_fit)
  # the dropped chains at the kept medians, but the first parameter at the
  # bottom of its range, outside the kept 90 % interval
  at <- rep(apply(tf, 2, median), each = 10)
  dropped <- matrix(at, 10)
  dropped[, 1] <- 0.001
  moved <- bayesbem:::moved_parameters(seb_fit, dropped)
  expect_length(moved, 1)
  name <- colnames(physical)[1]
  expect_match(moved, paste0("^", name, ": "))
  low <- bayesbem:::unscale_t1(0.001, seb_fit$data$scaling, 1)
  expect_lt(low, quantile(physical[, 1], 0.05))
  expect_match(moved, format(signif(low, 3)), fixed = TRUE)
  expect_identical(bayesbem:::moved_parameters(seb_fit, matrix(at, 10)), character())
  expect_identical(bayesbem:::moved_parameters(seb_fit, NULL), character())
})

test_that("rstan's diagnostic warnings are told by the function that raised them", {
  skip_on_cran()
  short <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh_grid,
                    data = bayesbem:::koh_stan_data(koh_data(seb_field, seb_sim), koh_priors(),
                                                    NULL, "grid"),
                    chains = 2, iter = 30, seed = 1, refresh = 0)
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
  expect_error(bayesbem:::collect_chains(results, identity, NULL), "out of memory",
               class = "bayesbem_error_sampling")
})

test_that("a list of starting values gives each chain its own", {
  skip_on_cran()
  starts <- list(list(tf = c(0.2, 0.2, 0.2)), list(tf = c(0.8, 0.8, 0.8)))
  fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 2, iter = 20, seed = 1,
                                    init = starts),
                          classes = "bayesbem_warning_convergence")
  expect_equal(lapply(fit$stanfit@inits, function(i) as.vector(i$tf)),
               list(rep(0.2, 3), rep(0.8, 3)))
})
