test_that("check_convergence() reports every parameter and the sampler", {
  skip_on_cran()
  fit <- shared_fit()
  conv <- check_convergence(fit, warn = FALSE)
  expect_s3_class(conv, "bayesbem_convergence")
  # tf, beta_eta, beta_delta, the lambdas, and the 7 terms of the linear emulator mean
  expect_equal(nrow(conv), 3 + 6 + 3 + 3 + 7)
  expect_named(conv, c("variable", "rhat", "ess_bulk", "ess_tail", "ok"))
  expect_equal(conv$ok, conv$rhat < 1.01 & conv$ess_bulk >= 200 & conv$ess_tail >= 200)
  sp <- attr(conv, "sampler")
  expect_named(sp, c("divergent", "treedepth_hits", "max_treedepth", "ebfmi"))
  expect_length(sp$ebfmi, 2)
  expect_true(all(sp$ebfmi > 0))
  expect_output(print(conv), "divergent transitions")
})

test_that("a deliberately short run gets a classed convergence warning", {
  skip_on_cran()
  expect_warning(
    calibrate(seb_field, seb_sim, chains = 2, iter = 40, seed = test_seed(1), refresh = 0),
    class = "bayesbem_warning_convergence"
  )
})

test_that("a subset of the convergence table prints", {
  conv <- check_convergence(seb_fit, warn = FALSE)
  expect_output(print(conv[, c("variable", "rhat")]),
                sprintf("beta_eta\\[temp\\] +%.3f", conv$rhat[conv$variable == "beta_eta[temp]"]))
  expect_output(print(conv[conv$rhat > 0, ]), sprintf("of %d parameters", nrow(conv)))
})

test_that("tree-depth hits and a low E-BFMI are warned about like the others", {
  withr::local_options(cli.num_colors = 1)
  conv <- check_convergence(seb_fit, rhat_max = 10, ess_min = 1, warn = FALSE)
  attr(conv, "sampler")$divergent <- 0
  expect_no_warning(bayesbem:::warn_convergence(conv))
  attr(conv, "sampler")$treedepth_hits <- 7
  attr(conv, "sampler")$ebfmi <- c(0.25, 0.9)
  expect_warning(bayesbem:::warn_convergence(conv), class = "bayesbem_warning_convergence")
  expect_snapshot(bayesbem:::warn_convergence(conv))
})

test_that("chains that disagree only on the emulator's hyperparameters get their own hint", {
  withr::local_options(cli.num_colors = 1)
  conv <- check_convergence(seb_fit, ess_min = 1, warn = FALSE)
  # the emulator's correlation parameters, variance and mean coefficients
  expect_setequal(attr(conv, "emulator"),
                  grep("^(beta_eta\\[|lambda_eta$|b\\[)", conv$variable, value = TRUE))
  conv$rhat <- 1
  conv$rhat[conv$variable %in% c("beta_eta[temp]", "lambda_eta")] <- 1.3
  expect_snapshot(bayesbem:::warn_convergence(conv))
  # a calibration parameter or a sampler problem as well: the general hint
  for (change in list(function(x) { x$rhat[x$variable == "equipment_power_density"] <- 1.05; x },
                      function(x) { attr(x, "sampler")$divergent <- 3; x })) {
    w <- expect_warning(bayesbem:::warn_convergence(change(conv)),
                        class = "bayesbem_warning_convergence")
    expect_no_match(conditionMessage(w), "Only the emulator")
    expect_match(conditionMessage(w), "Run more iterations")
  }
})

test_that("chains kept in a minor mode of the calibration get their own hint", {
  withr::local_options(cli.num_colors = 1)
  conv <- check_convergence(seb_fit, ess_min = 1, warn = FALSE)
  expect_identical(attr(conv, "kept_moved"), integer(0))
  conv$rhat <- 1
  conv$rhat[conv$variable == "equipment_power_density"] <- 1.3
  attr(conv, "kept_moved") <- 2:3
  expect_snapshot(bayesbem:::warn_convergence(conv))
})

test_that("a fit that hits the maximum tree depth says so, and rstan's own warnings are not shown", {
  skip_on_cran()
  warnings <- list()
  withCallingHandlers(
    fit <- calibrate(seb_field, seb_sim, chains = 2, iter = 100, seed = test_seed(1),
                     control = list(max_treedepth = 2)),
    warning = function(w) {
      warnings[[length(warnings) + 1L]] <<- w
      invokeRestart("muffleWarning")
    })
  # bayesbem's own only (a run this short may also pile a posterior against
  # a range limit, bayesbem_warning_range_limit), and one on convergence
  expect_true(all(vapply(warnings, inherits, logical(1), "bayesbem_warning")))
  convergence <- Filter(function(w) inherits(w, "bayesbem_warning_convergence"), warnings)
  expect_length(convergence, 1)
  expect_match(conditionMessage(convergence[[1]]), "hit the maximum tree depth \\(2\\)")
  expect_gt(attr(check_convergence(fit, warn = FALSE), "sampler")$treedepth_hits, 0)
})

test_that("a posterior piled against a limit of its range is named with the limit", {
  # the case study's fan efficiency piles at the largest value the runs
  # tried (on its reciprocal scale, the share of draws within 2 % of it)
  limits <- bayesbem:::range_limits(seb_fit)
  expect_equal(limits$parameter, "fan_total_efficiency")
  expect_equal(limits$limit, "maximum")
  expect_equal(limits$value, max(seb_fit$data$sim$fan_total_efficiency))
  u <- posterior::as_draws_matrix(posterior::subset_draws(seb_fit$draws, variable = "tf[1]"))
  expect_equal(limits$share, mean(u > 0.98))
  expect_warning(bayesbem:::warn_range_limits(seb_fit), "fan_total_efficiency at its maximum, 0.816",
                 class = "bayesbem_warning_range_limit")
  # a quarter of the equipment's draws within 1 % of its minimum
  piled <- seb_fit
  arr <- unclass(posterior::as_draws_array(piled$draws))
  draws <- length(arr[, , "tf[2]"])
  arr[, , "tf[2]"] <- withr::with_seed(1, ifelse(seq_len(draws) %% 4 == 0, 0.01,
                                                 stats::runif(draws, 0.3, 0.7)))
  piled$draws <- posterior::as_draws_array(arr)
  limits <- bayesbem:::range_limits(piled)
  expect_equal(limits$parameter, c("fan_total_efficiency", "equipment_power_density"))
  expect_equal(limits$limit, c("maximum", "minimum"))
  expect_equal(limits$share[2], 0.25, tolerance = 0.01)
  expect_equal(limits$value[2], min(seb_fit$data$sim$equipment_power_density))
  # a flat posterior is not piled
  arr[, , "tf[2]"] <- withr::with_seed(2, stats::runif(draws))
  piled$draws <- posterior::as_draws_array(arr)
  expect_equal(bayesbem:::range_limits(piled)$parameter, "fan_total_efficiency")
})
