test_that("the shipped fit's verdicts agree with the paper's findings", {
  x <- identifiability(seb_fit, ndraws = 100)
  expect_s3_class(x, "bayesbem_identifiability")
  verdict <- stats::setNames(x$verdict, x$parameter)
  # the paper: equipment power density is determined (about 5-18 W/m2 of
  # 3-30), fan efficiency hardly (spread over its range), and with flat
  # priors the discrepancy holds no parameter's effect. Equipment density's
  # posterior sd is about half the prior's (3.4 of 6.8 W/m2 in a converged
  # case-study fit), near the rule's 0.5 line: a rebuilt seb_fit can land on
  # "partly learnt" (the paper's interval and the ranking below still hold).
  epd <- stats::quantile(posterior::as_draws_matrix(seb_fit)[, "equipment_power_density"],
                         c(0.05, 0.95))
  expect_true(epd[[1]] > 4 && epd[[2]] < 19)
  expect_equal(verdict[["equipment_power_density"]], "learnt")
  expect_equal(x$parameter[which.min(x$sd_ratio)], "equipment_power_density")
  expect_true(verdict[["fan_total_efficiency"]] %in% c("partly learnt", "prior-driven"))
  expect_false(any(verdict == "confounded with the discrepancy"))
  # posterior and prior spreads, independently: the flat prior's sd is the
  # design range over sqrt(12)
  draws <- posterior::as_draws_matrix(seb_fit)
  expect_equal(x$posterior_sd, unname(apply(unclass(draws)[, x$parameter], 2, stats::sd)))
  # flat priors in physical units, whatever scale the emulator works on
  expect_equal(x$prior_sd,
               unname(apply(seb_sim[x$parameter], 2, function(v) diff(range(v)))) / sqrt(12))
  expect_match(attr(x, "summary"), "The data determined equipment_power_density")
})

test_that("the shift is the discrepancy's projection on the simulator's sensitivity", {
  data <- seb_fit$data
  g <- bayesbem:::gp_geometry(data, bayesbem:::scale_newdata(data, data$field[data$names$x]), "grid")
  par <- bayesbem:::draw_parameters(seb_fit, 5)[[3]]
  out <- bayesbem:::discrepancy_projection(g, par, data)
  # independently: the sensitivity by finite differences of the emulator's
  # mean given the runs, on the dense (non-grid) algebra
  gd <- bayesbem:::gp_geometry(data, NULL, "dense")
  em <- function(tf) {
    par$tf <- tf
    fm <- bayesbem:::field_given_runs(bayesbem:::residual_geometry(gd, par), par)
    fm$mean + bayesbem:::emulator_mean(gd$xf, tf, par$coef)
  }
  up <- par$tf
  up[2] <- up[2] + 0.01
  down <- par$tf
  down[2] <- down[2] - 0.01
  sens <- (em(up) - em(down)) / 0.02
  cond <- bayesbem:::koh_conditional(g, par)
  delta <- cond$mean[13:24]
  expect_equal(out$shift[2], sum(sens * delta) / sum(sens^2), tolerance = 1e-6)
  expect_equal(out$alignment[2], abs(stats::cor(sens, delta)), tolerance = 1e-6)
})

test_that("a parameter held away from the truth by a specific prior is confounded", {
  case <- synthetic_case("none")
  # the truth is 15 W/m2: a specific prior at 24 holds the parameter there
  priors <- koh_priors(tf = list(equipment_power_density = prior_normal(24, 0.05)))
  train <- case$field[-synthetic_held_out, c("y", "temp", "rh", "solar")]
  held <- suppressWarnings(
    calibrate(train, case$base$data$sim, priors = priors, chains = 2, iter = 500, seed = test_seed(3),
              refresh = 0),
    classes = "bayesbem_warning_convergence")
  x <- identifiability(held, ndraws = 60)
  verdict <- stats::setNames(x$verdict, x$parameter)
  expect_equal(verdict[["equipment_power_density"]], "confounded with the discrepancy")
  # the same data with flat priors: nothing confounded
  base <- identifiability(case$base, ndraws = 60)
  expect_false(any(base$verdict == "confounded with the discrepancy"))
  expect_s3_class(plot(x), "ggplot")
  d <- plot_identifiability_data(x)
  expect_equal(d$abs_shift, pmax(abs(x$shift), 0.01))
})

test_that("identifiability() checks its arguments", {
  expect_error(identifiability(list()), class = "bayesbem_error_argument")
  expect_error(identifiability(seb_fit, ndraws = 0), class = "bayesbem_error_argument")
  expect_error(identifiability(seb_fit, draws = 5), class = "rlib_error_dots_nonempty")
  expect_error(plot_identifiability_data(seb_fit), class = "bayesbem_error_argument")
})

test_that("on two outputs, each parameter's information is shared out by output", {
  skip_on_cran()
  fit <- two_output_fit()
  id <- identifiability(fit, ndraws = 20)
  expect_equal(id$informed_by_electricity + id$informed_by_gas, c(1, 1))
  rownames(id) <- id$parameter
  # plug loads are what the electricity bills measure; infiltration moves
  # the embedded model's gas far more than plug loads do, so gas holds a
  # far larger share of its information.
  # Which meter holds more of infiltration's depends on the draws (the
  # sensitivities at them), so only the contrast is asserted.
  expect_gt(id["equipment_power_density", "informed_by_electricity"], 0.6)
  expect_gt(id["infiltration_per_exterior_area", "informed_by_gas"],
            id["equipment_power_density", "informed_by_gas"] + 0.2)
  # the spreads are the shared parameters', each output's shift its own
  one <- identifiability(output_fit(fit, "gas"), ndraws = 20)
  expect_equal(id$sd_ratio, one$sd_ratio)
  expect_equal(id$shift_gas, one$shift)
  # the summary names, for each parameter, the output with the larger share
  for (p in id$parameter) {
    best <- if (id[p, "informed_by_gas"] > id[p, "informed_by_electricity"]) "gas" else "electricity"
    expect_match(attr(id, "summary"), paste(p, best), fixed = TRUE)
  }
})
