test_that("paired savings equal the simulator's by hand at the same posterior draws", {
  sim <- linear_seb_simulator()
  retrofit <- scenario(sim, scale = c(equipment_power_density = 0.8), name = "efficient")
  s <- savings(seb_fit, sim, retrofit, ndraws = 20, discrepancy = "none")
  d <- used_draws(seb_fit, s$draw)
  # the linear simulator saves 40 * 0.2 * epd in every period
  expect_equal(unname(s$savings), matrix(8 * d$equipment_power_density, 20, 12),
               tolerance = 1e-6)
  expect_equal(s$baseline - s$retrofit, s$savings)
  sm <- summary(s)
  expect_equal(sm$period, c(as.character(1:12), "total"))
  expect_equal(sm$savings[13], 12 * 8 * mean(d$equipment_power_density), tolerance = 1e-6)
  expect_equal(sm$percent[13], 100 * sm$savings[13] / sm$baseline[13])
  expect_true(all(sm$lower <= sm$savings & sm$savings <= sm$upper))
  out <- capture.output(print(s))
  expect_match(out[1], "efficient against as calibrated")
  expect_match(paste(out, collapse = "\n"), "total savings")
  # the Monte Carlo error of the total's mean, by hand
  mcse <- signif(stats::sd(rowSums(s$savings)) / sqrt(nrow(s$savings)), 2)
  expect_match(paste(out, collapse = "\n"), paste("Monte Carlo standard error of the total:", mcse),
               fixed = TRUE)
})

test_that("the discrepancy under the retrofit is the assumption chosen", {
  sim <- linear_seb_simulator()
  retrofit <- scenario(sim, scale = c(equipment_power_density = 0.8))
  withr::local_seed(5)
  same <- savings(seb_fit, sim, retrofit, ndraws = 8, discrepancy = "same")
  withr::local_seed(5)
  prop <- savings(seb_fit, sim, retrofit, ndraws = 8, discrepancy = "proportional")
  none <- savings(seb_fit, sim, retrofit, ndraws = 8, discrepancy = "none")
  # an unchanged discrepancy cancels from the savings
  expect_equal(same$savings, none$savings, tolerance = 1e-8)
  expect_false(isTRUE(all.equal(same$baseline, none$baseline)))
  # a proportional one scales with the simulated use: same draws of delta
  delta <- same$baseline - none$baseline
  expect_equal(prop$retrofit, none$retrofit + delta * none$retrofit / none$baseline,
               tolerance = 1e-8)
})

test_that("a scenario with no change saves exactly nothing", {
  sim <- linear_seb_simulator()
  for (d in c("same", "proportional", "none")) {
    s <- savings(seb_fit, sim, scenario(sim), ndraws = 6, discrepancy = d)
    expect_identical(max(abs(s$savings)), 0)
  }
})

test_that("baseline and retrofit over other periods are refused", {
  sim <- linear_seb_simulator()
  other <- linear_seb_simulator(transform(seb_field[c("temp", "rh", "solar")], temp = temp + 1))
  expect_snapshot(savings(seb_fit, sim, other, ndraws = 4), error = TRUE)
  expect_error(savings(seb_fit, sim, linear_seb_simulator(seb_field[1:6, c("temp", "rh", "solar")])),
               class = "bayesbem_error_scenario")
  expect_error(savings(seb_fit, sim, sim, discrepancy = "sam"), class = "bayesbem_error_argument")
})

test_that("avoided energy is the adjusted baseline less the measured use", {
  sim <- linear_seb_simulator()
  withr::local_seed(8)
  adjusted <- predict_scenario(seb_fit, sim, ndraws = 20)$y
  measured <- 0.8 * seb_field$y
  withr::local_seed(8)
  a <- avoided_energy(seb_fit, sim, measured, ndraws = 20)
  expect_equal(a$draws, adjusted)
  tab <- a$table
  expect_equal(tab$avoided[1:12], colMeans(adjusted) - measured)
  expect_equal(tab$avoided[13], sum(tab$avoided[1:12]))
  expect_equal(tab$obs[13], sum(measured))
  expect_equal(a$fsu$fsu[1], (tab$upper[13] - tab$lower[13]) / 2 / tab$avoided[13])
  expect_output(print(a), "fractional savings uncertainty")
  expect_error(avoided_energy(seb_fit, sim, measured[1:5]), class = "bayesbem_error_argument")
  expect_error(avoided_energy(seb_fit, sim, rep(NA_real_, 12)), class = "bayesbem_error_argument")
  # the discrepancy choice is predict_scenario()'s
  withr::local_seed(8)
  alone <- predict_scenario(seb_fit, sim, ndraws = 20, discrepancy = "none")$y
  withr::local_seed(8)
  expect_equal(avoided_energy(seb_fit, sim, measured, ndraws = 20, discrepancy = "none")$draws,
               alone)
})

test_that("avoided energy leaves out the periods without a measurement", {
  sim <- linear_seb_simulator()
  measured <- c(0.8 * seb_field$y[1:6], rep(NA, 6))
  withr::local_seed(8)
  all <- avoided_energy(seb_fit, sim, 0.8 * seb_field$y, ndraws = 20)
  withr::local_seed(8)
  half <- avoided_energy(seb_fit, sim, measured, ndraws = 20)
  expect_equal(half$table$period, c(as.character(1:6), "total"))
  expect_equal(half$draws, all$draws[, 1:6])
  expect_equal(half$table$avoided[7], sum(all$table$avoided[1:6]))
  expect_output(print(half), "over 6 measured periods of 12")
})

test_that("Guideline 14's savings uncertainty follows its Annex B formula", {
  # by hand from the fit's training residuals
  obs <- seb_field$y
  withr::local_seed(9)
  pred <- colMeans(predict(seb_fit, summary = FALSE))
  withr::local_seed(9)
  fsu <- guideline14_fsu(seb_fit, m = 12, fraction = 0.2, level = 0.9)
  res <- obs - pred
  cv <- sqrt(sum(res^2) / 11) / mean(obs)
  rho <- sum(res[-1] * res[-12]) / sum(res^2)
  n_eff <- if (rho > 0) 12 * (1 - rho) / (1 + rho) else 12
  expect_equal(fsu, qt(0.95, 11) * 1.26 * cv * sqrt(12 / n_eff * (1 + 2 / n_eff) / 12) / 0.2)
})

test_that("savings and avoided energy of an extended fit take its covariates", {
  skip_on_cran()
  sim <- linear_seb_simulator()
  working <- data.frame(working_days = c(21, 20, 21, 22, 23, 20, 23, 22, 21, 23, 20, 21))
  ext <- suppressWarnings(extend(seb_fit, with = "working_days", covariates = working, chains = 2,
                                 iter = 400, refresh = 0),
                          classes = "bayesbem_warning_convergence")
  retrofit <- scenario(sim, scale = c(equipment_power_density = 0.8))
  expect_error(savings(ext, sim, retrofit, ndraws = 4), class = "bayesbem_error_columns")
  one_more <- data.frame(working_days = working$working_days + 1)
  s <- withr::with_seed(3, savings(ext, sim, retrofit, ndraws = 20, covariates = working))
  s1 <- withr::with_seed(3, savings(ext, sim, retrofit, ndraws = 20, covariates = one_more))
  gamma <- posterior::as_draws_df(ext)$`gamma[working_days]`[s$draw]
  # a working day more adds its coefficient to every month's use, draw by
  # draw, under both scenarios: the savings do not change
  expect_equal(unname(s1$baseline - s$baseline), matrix(gamma, 20, 12), tolerance = 1e-6)
  expect_equal(s1$savings, s$savings, tolerance = 1e-8)
  after <- 0.9 * seb_field$y
  a <- withr::with_seed(4, avoided_energy(ext, sim, after, ndraws = 20, covariates = working))
  a1 <- withr::with_seed(4, avoided_energy(ext, sim, after, ndraws = 20, covariates = one_more))
  gamma <- posterior::as_draws_df(ext)$`gamma[working_days]`[a$draw]
  expect_equal(unname(a1$draws - a$draws), matrix(gamma, 20, 12), tolerance = 1e-6)
  expect_error(avoided_energy(ext, sim, after, ndraws = 4, covariates = working[1:6, , drop = FALSE]),
               class = "bayesbem_error_covariates")
})
