# Stage 2 on several outputs: the outputs share tf and nothing else, so its
# log density is the sum over outputs of the field outputs' density given
# the runs (each at its own fixed emulator), plus the priors: tf's once,
# each output's discrepancy and noise priors.
test_that("the K-output stage-2 log density is the sum of the outputs' (separable)", {
  skip_on_cran()
  withr::local_seed(41)
  tables <- random_outputs_data()
  d <- koh_data(tables$field, tables$sim)
  # a discrepancy term on gas only: its coefficient shifts gas's rows alone
  d <- bayesbem:::add_output_terms(d, list(gas = data.frame(occupancy = runif(6))))
  priors <- koh_priors(emulator_mean = "constant")
  p <- 2
  q <- 3
  emulators <- lapply(d$outputs, function(o) {
    list(beta_eta = stats::runif(p + q, 0.5, 3), lambda_eta = stats::rgamma(1, 10, 10),
         b = stats::rnorm(1))
  })
  sd <- bayesbem:::modular_stan_data(d, priors, emulators)
  expect_equal(sd$K, 2L)
  expect_equal(as.numeric(sd$output), rep(1:2, c(7, 6)))
  model <- koh_model_for(sd)
  for (i in 1:3) {
    pars <- list(tf = as.array(stats::runif(q)), rho_delta = as.array(stats::runif(2 * p, 0.3, 0.99)),
                 lambda_delta = as.array(stats::rgamma(2, 10, 0.3)),
                 lambda_e = as.array(stats::rgamma(2, 10, 0.03)), gamma = as.array(stats::rnorm(1)))
    expected <- 0
    for (k in 1:2) {
      one <- d$outputs[[k]]
      dense <- bayesbem:::koh_stan_data(one, priors, structure = "dense")
      em <- emulators[[k]]
      pars_k <- list(tf = pars$tf, rho_eta = exp(-em$beta_eta / 4), lambda_eta = em$lambda_eta,
                     b = em$b, rho_delta = pars$rho_delta[(k - 1) * p + seq_len(p)],
                     lambda_delta = pars$lambda_delta[k], lambda_e = pars$lambda_e[k],
                     gamma = if (k == 2) pars$gamma else numeric())
      expected <- expected + reference_field_given_runs(dense, pars_k)
    }
    expected <- expected + reference_tf_prior(sd, pars$tf) +
      sum(stats::dbeta(pars$rho_delta, sd$rho_delta_a, sd$rho_delta_b, log = TRUE)) +
      sum(stats::dgamma(pars$lambda_delta, sd$lambda_delta_shape, sd$lambda_delta_rate, log = TRUE)) +
      sum(stats::dgamma(pars$lambda_e, sd$lambda_e_shape, sd$lambda_e_rate, log = TRUE)) +
      sum(stats::dnorm(pars$gamma, 0, sd$gamma_sd, log = TRUE))
    expect_equal(stan_log_density(model, pars), expected, tolerance = 1e-8)
  }
})

test_that("the K-output stage-2 log density is the sum of the outputs' (basis)", {
  skip_on_cran()
  withr::local_seed(42)
  tables <- random_outputs_data(n = 9, runs = 8)
  d <- koh_data(tables$field, tables$sim)
  priors <- koh_priors()
  n_b <- sum(bayesbem:::mean_selection(priors, 2, 3))
  emulators <- lapply(d$outputs, function(o) {
    list(beta_eta = rep(1, 5), lambda_eta = 1, b = numeric(n_b),
         basis = bayesbem:::basis_emulator(o, variance = 0.99))
  })
  sd <- bayesbem:::basis_stan_data(d, priors, emulators)
  pcs <- vapply(emulators, function(e) length(e$basis$components), integer(1))
  expect_equal(as.numeric(sd$pc_output), rep(1:2, pcs))
  model <- koh_model_for(sd, "koh_basis")
  for (i in 1:3) {
    pars <- list(tf = as.array(stats::runif(3)), rho_delta = as.array(stats::runif(4, 0.3, 0.99)),
                 lambda_delta = as.array(stats::rgamma(2, 10, 0.3)),
                 lambda_e = as.array(stats::rgamma(2, 10, 0.03)), gamma = numeric(0),
                 phi = numeric(0))
    refs <- lapply(1:2, function(k) {
      one_sd <- bayesbem:::basis_stan_data(d$outputs[[k]], priors, emulators[[k]])
      reference_basis(one_sd, emulators[[k]]$basis,
                      list(tf = pars$tf, rho_delta = pars$rho_delta[(k - 1) * 2 + 1:2],
                           lambda_delta = pars$lambda_delta[k], lambda_e = pars$lambda_e[k]))$lp
    })
    # each reference holds tf's prior; tf is sampled as tf_u, with its Jacobian
    u <- bayesbem:::linear_box_inverse(pars$tf)
    a <- sd$tf_edge
    jacobian <- sum(log(stats::plogis(u / a) - stats::plogis((u - 1) / a)))
    expected <- refs[[1]] + refs[[2]] - reference_tf_prior(sd, pars$tf) + jacobian
    stan_pars <- c(list(tf_u = as.array(u)), pars[names(pars) != "tf"])
    expect_equal(basis_log_density(model, sd, stan_pars), expected, tolerance = 1e-8)
  }
})

test_that("one output in a long table gives the one-output fit, draw for draw", {
  skip_on_cran()
  long_field <- cbind(output = "electricity", seb_field)
  long_sim <- cbind(output = "electricity", seb_sim)
  one <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 1, iter = 300, seed = test_seed(5),
                                    progress = FALSE))
  long <- suppressWarnings(calibrate(long_field, long_sim, chains = 1, iter = 300, seed = test_seed(5),
                                     progress = FALSE))
  expect_s3_class(long, "bayesbem_fit_outputs")
  expect_identical(posterior::as_draws_array(output_fit(long, "electricity")),
                   posterior::as_draws_array(one))
  expect_identical(posterior::as_draws_array(output_fit(long, 1)), posterior::as_draws_array(one))
})

test_that("a fit on two outputs: shared draws, each output a fit of its own", {
  skip_on_cran()
  fit <- two_output_fit()
  full <- posterior::as_draws_matrix(fit$draws)
  # every variable once: the shared ones plain, each output's own prefixed
  variables <- posterior::variables(fit$draws)
  expect_false(anyDuplicated(variables) > 0)
  expect_true(all(c("tf[1]", "lp__", "electricity:lambda_e", "gas:lambda_e",
                    "gas:rho_delta[1]") %in% variables))
  for (k in c("electricity", "gas")) {
    one <- output_fit(fit, k)
    expect_s3_class(one, "bayesbem_fit")
    # an output's view: the shared draws and its own, as a one-output fit names them
    expect_identical(bayesbem:::stan_draws(one, "tf"), unname_draws(full[, c("tf[1]", "tf[2]")]))
    expect_identical(as.vector(bayesbem:::stan_draws(one, "lambda_e")),
                     as.vector(full[, paste0(k, ":lambda_e")]))
    p <- one$data$p
    expect_identical(as.vector(bayesbem:::stan_draws(one, "rho_delta")),
                     as.vector(full[, sprintf("%s:rho_delta[%d]", k, seq_len(p))]))
    expect_identical(as.vector(bayesbem:::stan_draws(one, "lambda_eta")),
                     rep(one$emulator$lambda_eta, nrow(full)))
    expect_identical(one$sampler, fit$sampler)
    # the chains' starting values, as a one-output fit records them
    j <- match(k, c("electricity", "gas"))
    expect_identical(one$inits[[2]]$lambda_e, as.vector(fit$inits[[2]]$lambda_e)[j])
    expect_identical(one$inits[[2]]$tf, fit$inits[[2]]$tf)
  }
  conv <- check_convergence(fit, warn = FALSE)
  expect_true(all(c("electricity:lambda_e", "gas:lambda_e", "equipment_power_density") %in%
                    conv$variable))
  expect_equal(sum(conv$variable == "equipment_power_density"), 1L)
  draws <- posterior::as_draws_array(fit)
  expect_true(all(c("gas:lambda_delta", "electricity:beta_delta[temp]") %in%
                    posterior::variables(draws)))
  expect_snapshot(output_fit(fit, "water"), error = TRUE)
})

test_that("each output's emulator is checked against its own meter", {
  skip_on_cran()
  fit <- two_output_fit()
  sim <- two_output_simulator()
  gas_fit <- output_fit(fit, "gas")
  check <- validate_emulator(gas_fit, output_simulator(sim, "gas"), ndraws = 3)
  # gas's 11 field periods (no August bill), at each draw, against gas runs
  expect_equal(nrow(check$table), 3 * 11)
  expect_equal(unique(check$table$draw), attr(bayesbem:::draw_parameters(gas_fit, 3), "index"))
  draws <- as.data.frame(posterior::as_draws_df(posterior::as_draws(gas_fit)))
  at <- as.list(draws[check$table$draw[1], fit$data$names$t])
  base <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  truth <- bem_monthly(utils::modifyList(base, at), epw_monthly(shipped_epw(2013)))$gas[-8]
  expect_equal(check$table$simulated[1:11], truth, tolerance = 1e-10)
  # or every output at once, one run per draw for all
  runs <- new.env()
  counting <- counting_simulator(runs, sim)
  checks <- validate_emulator(fit, counting, ndraws = 3)
  expect_equal(runs$calls, 3)
  expect_named(checks, c("electricity", "gas"))
  expect_equal(checks$gas$table, check$table)
  expect_output(print(checks), "gas:")
})

test_that("scenarios of a fit on several outputs: one run per draw for all, and their total", {
  skip_on_cran()
  fit <- two_output_fit()
  sim <- two_output_simulator()
  runs <- new.env()
  counting <- counting_simulator(runs, sim)
  set.seed(2)
  p <- predict_scenario(fit, counting, ndraws = 20, total = c(electricity = 1, gas = 2))
  expect_equal(runs$calls, 20)
  expect_equal(p$total, p$outputs$electricity$y + 2 * p$outputs$gas$y)
  s <- summary(p)
  expect_equal(unique(s$output), c("electricity", "gas", "total"))
  expect_equal(s$mean[s$output == "total" & s$period == "total"], mean(rowSums(p$total)))
  # each output's prediction is that output's own, from the same draws
  set.seed(2)
  alone <- predict_scenario(output_fit(fit, "electricity"), output_simulator(sim, "electricity"),
                            ndraws = 20)
  expect_equal(p$outputs$electricity$y, alone$y)
  expect_equal(p$outputs$gas$draw, alone$draw)
  expect_error(predict_scenario(seb_fit, sim, total = c(a = 1)), class = "bayesbem_error_argument")
})

test_that("every verb takes a fit on several outputs: each output's result, from one run per draw", {
  skip_on_cran()
  fit <- two_output_fit()
  sim <- two_output_simulator()
  gas <- output_fit(fit, "gas")
  gas_sim <- output_simulator(sim, "gas")
  # the simulator at the posterior: one run per draw serves both outputs
  runs <- new.env()
  simulated <- posterior_simulate(fit, counting_simulator(runs, sim), ndraws = 20)
  expect_equal(runs$calls, 20)
  expect_equal(simulated[simulated$output == "gas", -1],
               posterior_simulate(gas, gas_sim, ndraws = 20), ignore_attr = TRUE)
  # avoided energy: each output's, and the weighted total of their totals
  after <- list(electricity = rep(1500, 12), gas = c(rep(800, 11), NA))
  # (the same noise draws: gas's come after electricity's)
  avoided <- withr::with_seed(1, avoided_energy(fit, sim, after, ndraws = 20,
                                                total = c(electricity = 1, gas = 2)))
  own <- withr::with_seed(1, {
    avoided_energy(output_fit(fit, "electricity"), output_simulator(sim, "electricity"),
                   after$electricity, ndraws = 20)
    avoided_energy(gas, gas_sim, after$gas, ndraws = 20)
  })
  expect_equal(avoided$outputs$gas$table, own$table)
  totals <- lapply(avoided$outputs, function(a) rowSums(a$draws) - sum(a$obs))
  expect_equal(avoided$total, totals$electricity + 2 * totals$gas)
  s <- summary(avoided)
  expect_equal(s$avoided[s$output == "total"], mean(avoided$total))
  expect_equal(sum(s$output == "gas"), 12)  # 11 measured months and their total
  expect_error(avoided_energy(fit, sim, after$gas, ndraws = 20), class = "bayesbem_error_argument")
  expect_error(avoided_energy(gas, gas_sim, after$gas, total = c(gas = 1)),
               class = "bayesbem_error_argument")
  # the diagnosis: each output's on its own
  e <- explain_discrepancy(fit, ndraws = 20, n_null = 30, regions = FALSE, seed = 1)
  expect_equal(as.data.frame(e$outputs$gas),
               as.data.frame(explain_discrepancy(gas, ndraws = 20, n_null = 30, regions = FALSE,
                                                 seed = 1)))
  expect_equal(unique(summary(e)$output), c("electricity", "gas"))
  expect_output(print(e), "gas")
  expect_error(explain_discrepancy(fit, covariates = data.frame(a = 1:12)),
               class = "bayesbem_error_covariates")
})

test_that("loo and compare_fits on several outputs: every output's rows, each output's table", {
  skip_on_cran()
  fit <- two_output_fit()
  l <- suppressWarnings(loo::loo(fit, ndraws = 60))
  # the pointwise densities are each output's own (paired draws)
  own <- lapply(fit$outputs, bayesbem:::loo_log_lik, ndraws = 60)
  expect_equal(nrow(l$pointwise), 12 + 11)
  expect_equal(l$estimates["elpd_loo", "Estimate"],
               suppressWarnings(loo::loo(do.call(cbind, own)))$estimates["elpd_loo", "Estimate"],
               tolerance = 0.05)
  cf <- suppressWarnings(compare_fits(fit, fit, ndraws = 60))
  expect_equal(cf$elpd$diff, 0)
  expect_equal(cf$discrepancy$output, c("electricity", "gas"))
  expect_equal(cf$discrepancy$shrinkage, c(0, 0))
  expect_equal(unique(cf$metrics$output), c("electricity", "gas"))
  expect_error(compare_fits(fit, output_fit(fit, "gas")), class = "bayesbem_error_argument")
  expect_error(compare_fits(fit, fit, newdata = seb_field, obs = seb_field$y),
               class = "bayesbem_error_argument")
})

test_that("savings of a fit on several outputs: each output's, and their priced total", {
  skip_on_cran()
  fit <- two_output_fit()
  runs <- new.env()
  counting <- counting_simulator(runs)
  led <- scenario(counting, set = c(lighting_power_density = 7))
  s <- savings(fit, scenario(counting), led, ndraws = 20, total = c(electricity = 0.2, gas = 0.05))
  # one run per draw and scenario serves both outputs
  expect_equal(runs$calls, 40)
  expect_equal(s$total, 0.2 * cbind(s$outputs$electricity$savings, rowSums(s$outputs$electricity$savings)) +
                 0.05 * cbind(s$outputs$gas$savings, rowSums(s$outputs$gas$savings)))
  # LED lighting saves electricity and costs heating gas
  expect_gt(mean(rowSums(s$outputs$electricity$savings)), 0)
  expect_lt(mean(rowSums(s$outputs$gas$savings)), 0)
  tab <- summary(s)
  expect_equal(unique(tab$output), c("electricity", "gas", "total"))
  expect_equal(tab$savings[tab$output == "total" & tab$period == "total"], mean(s$total[, 13]))
  expect_output(print(s), "weighted total")
})
