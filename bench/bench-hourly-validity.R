# Benchmark (issue 55, validity): calibration on hourly data with a known
# truth, and the savings it prices. Each problem: the embedded hourly model
# on the 2013 weather, three parameters (equipment power density,
# infiltration, cooling setpoint) drawn in the middle 60 % of their ranges,
# the simulator's use at them over the first `hours` hours plus AR(1) noise
# (phi 0.7, sd 0.5 kWh, a fifth of the mean hour) and, in odd problems, a
# load the model lacks (0.6 kWh in weekend hours 8-18: plug loads left on);
# 30 runs; calibrate() with noise_correlation = "ar1" (the additive
# discrepancy at this size). The retrofit (equipment x 0.7) is priced under
# the 2012 weather, a year of hours: savings() against the true savings (the
# simulator at the truth, baseline less retrofit; the hidden load, untouched
# by the retrofit, cancels), and avoided_energy() against the meter of the
# retrofitted building (truth, hidden load, new AR(1) noise): its interval
# from the draws and Guideline 14's (Annex B, the avoided energy +- FSU),
# each checked for the true savings.
# Reported per problem: the truth inside the 90 % intervals (and each
# parameter's posterior mean less the truth, in posterior sds), max R-hat,
# divergences, Guideline 14's hourly metrics of the simulator at the
# posterior (CV(RMSE) <= 30 %, |NMBE| <= 10 %), the savings and their
# interval, the FSUs and whether each interval holds the true savings.
# Targets: parameter and savings coverage 85-95 % over >= 20 problems.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-hourly-validity.R [problems: k or k1-k2] [hours] [chains]
#   BENCH_DRAWS: posterior draws per scenario (default 40).
#   BENCH_FITS=<folder> keeps each problem's fit for later runs (the savings
#   are then priced again on it).
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE, width = 200)
args <- commandArgs(trailingOnly = TRUE)
arg <- function(i, default) if (length(args) >= i) args[i] else default
spec <- as.integer(strsplit(arg(1, "20"), "-")[[1]])
problems <- if (length(spec) > 1L) seq(spec[1], spec[2]) else seq_len(spec)
hours <- as.integer(arg(2, "8760"))
chains <- as.integer(arg(3, "2"))
ndraws <- as.integer(Sys.getenv("BENCH_DRAWS", "40"))
fits_dir <- Sys.getenv("BENCH_FITS")

epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
pre <- bem_simulator(epw(2013), by = "hour")
post <- bem_simulator(epw(2012), by = "hour")
# the reporting-year simulator runs the retrofit below the design range's
# floor too, so that a low posterior draw can be retrofitted
floor <- post$parameters$parameter == "equipment_power_density"
post$parameters$min[floor] <- 0.7 * post$parameters$min[floor]
params <- c("equipment_power_density", "infiltration_per_exterior_area", "cooling_setpoint")
ranges <- pre$parameters[pre$parameters$parameter %in% params, ]
retrofit <- scenario(post, scale = c(equipment_power_density = 0.7), name = "retrofit")
keep <- seq_len(hours)
weekend_load <- function(x) 0.6 * (x$daytype_hour >= 24 + 8 & x$daytype_hour < 24 + 18)
# stationary AR(1) noise: the recursion starts from a unit-variance draw
ar1_noise <- function(n, phi = 0.7, sd = 0.5) {
  sd * as.numeric(stats::filter(stats::rnorm(n, sd = sqrt(1 - phi^2)), phi,
                                method = "recursive", init = stats::rnorm(1)))
}

one_problem <- function(k) {
  set.seed(2000 + k)
  width <- ranges$max - ranges$min
  truth <- as.list(stats::setNames(stats::runif(3, ranges$min + 0.2 * width,
                                                ranges$max - 0.2 * width), ranges$parameter))
  hidden <- k %% 2 == 1
  effect <- function(x) if (hidden) weekend_load(x) else 0
  use <- simulate_field(pre, truth)$y + effect(pre$x) + ar1_noise(nrow(pre$x))
  field <- data.frame(y = use, pre$x, time = pre$periods$start)[keep, ]
  runs <- simulate_design(pre, design_lhs(ranges, n = 30, seed = k))
  runs <- runs[rep((seq_len(30) - 1L) * nrow(pre$x), each = hours) + keep, ]
  file <- file.path(fits_dir, sprintf("validity_%d_%d_%d.rds", k, hours, chains))
  if (nzchar(fits_dir) && file.exists(file)) {
    cached <- readRDS(file)
  } else {
    start <- proc.time()[["elapsed"]]
    fit <- suppressWarnings(
      calibrate(field, runs, noise_correlation = "ar1", chains = chains, cores = 2, seed = k,
                refresh = 0),
      classes = "bayesbem_warning_convergence")
    cached <- list(fit = fit, fit_s = proc.time()[["elapsed"]] - start)
    if (nzchar(fits_dir)) saveRDS(cached, file)
  }
  fit <- cached$fit
  fit_s <- cached$fit_s
  s <- summary(fit)$parameters
  covered <- s$q5 <= unlist(truth)[rownames(s)] & unlist(truth)[rownames(s)] <= s$q95
  sampler <- attr(check_convergence(fit, warn = FALSE), "sampler")
  metrics <- calibration_metrics(fit, by = "hour")
  at_posterior <- metrics[metrics$prediction == "simulator", ]

  # pricing from its own seed, so that a cached fit prices the same
  set.seed(3000 + k)
  after <- truth
  after$equipment_power_density <- 0.7 * truth$equipment_power_density
  true_savings <- sum(simulate_field(post, truth)$y - simulate_field(post, after)$y)
  saved <- summary(suppressWarnings(savings(fit, post, retrofit, ndraws = ndraws),
                                    classes = "bayesbem_warning_extrapolation"))
  saved <- saved[nrow(saved), ]
  meter_after <- simulate_field(post, after)$y + effect(post$x) + ar1_noise(nrow(post$x))
  a <- suppressWarnings(avoided_energy(fit, post, meter_after, ndraws = ndraws),
                        classes = "bayesbem_warning_extrapolation")
  avoided <- a$table[nrow(a$table), ]
  g14 <- a$fsu$fsu[2] * abs(avoided$avoided)
  # each parameter's error in posterior sds, in the order of `params`
  z <- (s$mean - unlist(truth)[rownames(s)]) / s$sd
  data.frame(problem = k, hidden = hidden, covered = sprintf("%d/3", sum(covered)),
             z = paste(sprintf("%+.1f", z[match(params, rownames(s))]), collapse = " "),
             max_rhat = max(s$rhat), divergent = sampler$divergent, fit_s = fit_s,
             phi = mean(posterior::as_draws_df(fit)$phi),
             cvrmse = at_posterior$cvrmse, nmbe = at_posterior$nmbe,
             g14_calibrated = at_posterior$calibrated,
             true_savings = true_savings, savings = saved$savings,
             savings_covered = saved$lower <= true_savings && true_savings <= saved$upper,
             avoided = avoided$avoided, fsu_draws = a$fsu$fsu[1], fsu_g14 = a$fsu$fsu[2],
             avoided_covered = avoided$lower <= true_savings && true_savings <= avoided$upper,
             g14_covered = abs(avoided$avoided - true_savings) <= g14)
}

rows <- list()
for (k in problems) {
  rows[[length(rows) + 1L]] <- one_problem(k)
  print(rows[[length(rows)]], digits = 3, row.names = FALSE)
}
out <- do.call(rbind, rows)
n_covered <- sum(as.integer(substr(out$covered, 1, 1)))
cat(sprintf(paste0("\n%d problems of %d hours: parameters covered %d of %d (%.0f %%; without the hidden load %d of %d);",
                   " savings covered %d; avoided energy covered %d by the draws' interval, %d by Guideline 14's;",
                   " median FSU %.1f %% (Guideline 14 %.1f %%); Guideline 14's hourly limits met %d;",
                   " max R-hat %.3f, divergent %d\n"),
            nrow(out), hours, n_covered, 3 * nrow(out), 100 * n_covered / (3 * nrow(out)),
            sum(as.integer(substr(out$covered[!out$hidden], 1, 1))), 3 * sum(!out$hidden),
            sum(out$savings_covered), sum(out$avoided_covered), sum(out$g14_covered),
            100 * stats::median(out$fsu_draws), 100 * stats::median(out$fsu_g14),
            sum(out$g14_calibrated), max(out$max_rhat), sum(out$divergent)))
cat(sprintf("machine: %d cores; R %s; rstan %s; %s\n", parallel::detectCores(), getRversion(),
            packageVersion("rstan"), Sys.Date()))
