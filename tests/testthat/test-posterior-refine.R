refine_case <- function() {
  sim <- bem_simulator(shipped_epw(2013))
  top <- sim$parameters[sim$parameters$parameter %in%
                          c("equipment_power_density", "fan_total_efficiency",
                            "infiltration_per_exterior_area"), ]
  runs <- simulate_design(sim, design_lhs(top, n = 10, seed = 2))
  field <- data.frame(y = seb_field$y, sim$x)
  fit <- calibrate(field, runs, chains = 2, iter = 2000, seed = test_seed(7), cores = 2, refresh = 0)
  list(sim = sim, fit = fit)
}

test_that("refine_emulator() adds runs where the posterior lies until the emulator is trusted", {
  case <- refine_case()
  first <- validate_emulator(case$fit, case$sim, ndraws = 10)
  # ten runs for three parameters: the emulator's error moves the calibration
  expect_false(first$trusted)
  expect_gt(max(abs(first$shift$shift)), 0.5)
  warned <- FALSE
  expect_message(
    refined <- withCallingHandlers(
      refine_emulator(case$fit, case$sim, n = 6, rounds = 2, ndraws = 10, seed = 1),
      bayesbem_warning_emulator = function(w) {
        warned <<- TRUE
        invokeRestart("muffleWarning")
      }),
    class = "bayesbem_message_refine")
  r <- refined$refinement
  expect_equal(r$round, seq_len(nrow(r)) - 1L)
  expect_equal(r$runs, 10 + 6 * r$round)
  expect_equal(r$trusted[1], first$trusted)
  expect_equal(r$max_shift[1], max(abs(first$shift$shift)))
  # it stops at the first trusted check, or after the rounds with a warning
  expect_equal(sum(r$trusted), as.integer(r$trusted[nrow(r)]))
  expect_equal(warned, !r$trusted[nrow(r)])
  expect_equal(nrow(r), if (r$trusted[nrow(r)]) which(r$trusted) else 3L)
  # round 1's runs, recomputed: design_posterior() on the given fit
  added <- simulate_design(case$sim, design_posterior(case$fit, 6, seed = 1))
  expect_equal(refined$data$sim[120 + seq_len(72), names(added)], added, ignore_attr = TRUE)
  # the last check is that of the returned fit, with the fit's settings
  last <- validate_emulator(refined, case$sim, ndraws = 10)
  expect_equal(r$coverage[nrow(r)], last$coverage)
  expect_equal(refined$checks[[nrow(r)]]$shift, last$shift)
  expect_equal(refined$settings[c("chains", "iter", "seed")], case$fit$settings[c("chains", "iter", "seed")])
})

test_that("refine_emulator() says when the emulator is still not trusted after its rounds", {
  case <- synthetic_case("none")
  other <- synthetic_simulator()
  # not the simulator of the fit's runs: its runs do not mend the emulator
  shifted <- simulator(function(params, x) 1.3 * other$fun(params, x), other$x, other$parameters)
  # (the refit on runs of two simulators need not converge)
  expect_warning(
    suppressMessages(suppressWarnings(
      out <- refine_emulator(case$base, shifted, n = 4, rounds = 1, ndraws = 4, seed = 1),
      classes = "bayesbem_warning_convergence")),
    class = "bayesbem_warning_emulator")
  expect_equal(out$refinement$round, 0:1)
  expect_equal(out$refinement$runs, c(30, 34))
  expect_false(any(out$refinement$trusted))
  expect_equal(nrow(out$data$sim), 34 * 48)
})

test_that("the added runs keep the fit's simulation periods and columns", {
  data <- seb_fit$data
  x <- unique(data$sim[data$names$x_sim])
  extra <- x[1:2, ]
  extra[[1]] <- extra[[1]] + 100
  added <- cbind(eta = 1, rbind(x, extra), stats::setNames(as.list(rep(0.5, data$q)), data$names$t))
  names(added)[1] <- data$names$eta
  kept <- bayesbem:::refinement_runs(data, added)
  expect_equal(nrow(kept), nrow(x))
  expect_equal(names(kept), names(data$sim))
  expect_error(bayesbem:::refinement_runs(data, added[-2]), class = "bayesbem_error_simulator")
  expect_error(bayesbem:::refinement_runs(data, added[-1, ]), class = "bayesbem_error_simulator")
  # seb_fit's runs came from EnergyPlus, whose solar input is not the weather file's
  sim <- bem_simulator(shipped_epw(2013))
  expect_snapshot(refine_emulator(seb_fit, sim, n = 2, ndraws = 2), error = TRUE)
})

test_that("refine_emulator() checks its inputs", {
  sim <- bem_simulator(shipped_epw(2013))
  expect_snapshot(refine_emulator(seb_fit, sim, n = 1), error = TRUE)
  expect_error(refine_emulator(seb_fit, sim, rounds = "2"), class = "bayesbem_error_argument")
  expect_error(refine_emulator(seb_fit, sim, seed = -1), class = "bayesbem_error_argument")
  expect_error(refine_emulator(list(), sim), class = "bayesbem_error_argument")
  expect_error(refine_emulator(seb_fit, sim, n_draws = 2), class = "rlib_error_dots_nonempty")
})

test_that("on several outputs a round's runs serve every output, and every emulator must be trusted", {
  skip_on_cran()
  fit <- two_output_fit()
  sim <- two_output_simulator()
  added <- simulate_design(sim, design_posterior(fit, n = 3, seed = 1))
  data <- bayesbem:::refined_data(fit, added)
  expect_equal(names(data$outputs), c("electricity", "gas"))
  for (k in names(data$outputs)) {
    expect_equal(bayesbem:::run_count(data$outputs[[k]]), 12 + 3)
    # the added runs at the output's own field periods (gas lacks August)
    expect_equal(nrow(data$outputs[[k]]$sim), nrow(fit$data$outputs[[k]]$sim) / 12 * 15)
  }
  expect_error(bayesbem:::refined_data(fit, added[added$output == "gas", ]),
               class = "bayesbem_error_simulator")
  # the outcome of the checks of both outputs
  checks <- validate_emulator(fit, sim, ndraws = 3)
  outcome <- bayesbem:::check_outcome(checks)
  expect_equal(outcome$trusted, checks$electricity$trusted && checks$gas$trusted)
  expect_equal(outcome$coverage, min(checks$electricity$coverage, checks$gas$coverage))
  expect_match(outcome$verdict, "^electricity: .* gas: ")
})
