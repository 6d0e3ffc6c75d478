# Benchmark (issue 55): the additive Hilbert-space discrepancy
# (calibrate(discrepancy_kernel = "additive"), R/gp-hsgp.R) against the
# paper's product kernel on the same data, where the product kernel is
# still cheap: the problems of bench-reliability.R at 365 days
# (bayesbem:::synthetic_problem(): the embedded model on the 2013 daily
# weather, three parameters, 30 runs, noise 2 % of the mean output,
# correct simulator), every sixth day held out. calibrate()'s defaults
# (basis emulator, 4 chains) but for the kernel. Per problem and
# kernel: each parameter's posterior mean and sd, the difference of the
# means in Monte Carlo standard errors of the difference, the truth inside
# the 90 % intervals, the held-out days' 90 % predictive intervals (mean
# width, coverage of the measured use), max R-hat, divergences, the
# sampling time and min bulk ESS per second. BENCH_DAYS (default 365): the
# days of the daily problems, evenly spaced over the year.
# With "hours": the same comparison on hourly data, the paper's dense
# likelihood against the additive one at sizes the dense one finishes: the
# embedded hourly model on the 2013 weather, `hours` hours from 1 June
# (cooling and the working week in them), the three parameters
# of bench-year-hours.R at mid-range, white noise (sd 0.5 kWh), 30 runs.
# Usage, from the package root, with bayesbem installed:
#   [BENCH_DAYS=n] Rscript bench/bench-discrepancy-kernel.R [problems, e.g. 1-3] [chains] [iter]
#   Rscript bench/bench-discrepancy-kernel.R hours [hours, e.g. 168,336] [chains] [iter]
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE, width = 200)
args <- commandArgs(trailingOnly = TRUE)
hourly <- length(args) > 0 && args[1] == "hours"
if (hourly) args <- args[-1]
span <- as.integer(strsplit(if (length(args) > 0) args[1] else "1-3", if (hourly) "," else "-")[[1]])
chains <- if (length(args) > 1) as.integer(args[2]) else 4L
iter <- if (length(args) > 2) as.integer(args[3])
days <- as.integer(Sys.getenv("BENCH_DAYS", "365"))

# An hourly problem of bench-year-hours.R's kind: `hours` hours from 1 June.
hourly_problem <- function(hours) {
  epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
  sim <- bem_simulator(epw, by = "hour")
  keep <- 24 * 151 + seq_len(hours)
  names <- c("equipment_power_density", "infiltration_per_exterior_area", "cooling_setpoint")
  params <- sim$parameters[sim$parameters$parameter %in% names, ]
  truth <- stats::setNames(as.list((params$min + params$max) / 2), params$parameter)
  use <- simulate_field(sim, truth, noise_sd = 0.5, seed = hours)
  runs <- simulate_design(sim, design_lhs(params, n = 30, seed = 2))
  runs <- runs[rep((seq_len(30) - 1L) * nrow(sim$x), each = hours) + keep, ]
  # the simulator of the window: the year run (the model carries its heat
  # from hour to hour), its hours kept
  window <- simulator(function(params, x) sim$fun(params, sim$x)[keep], sim$x[keep, ],
                      sim$parameters, periods = sim$periods[keep, ])
  list(field = use[keep, ], runs = runs, truth = truth, simulator = window)
}

one_fit <- function(problem, kernel, k) {
  held_out <- seq(6, nrow(problem$field), by = 6)
  start <- proc.time()[["elapsed"]]
  fit <- suppressWarnings(
    calibrate(problem$field[-held_out, ], problem$runs, discrepancy_kernel = kernel,
              chains = chains, iter = iter, cores = 2, seed = k, refresh = 0),
    classes = "bayesbem_warning_convergence")
  seconds <- proc.time()[["elapsed"]] - start
  s <- summary(fit)$parameters
  truth <- unlist(problem$truth)[rownames(s)]
  # held-out days through the simulator at 200 draws: the additive fit's
  # basis emulator knows the simulator only at its field rows
  y <- predict_scenario(fit, problem$simulator, ndraws = 200)$y[, held_out]
  pred <- data.frame(q5 = apply(y, 2, stats::quantile, 0.05),
                     q95 = apply(y, 2, stats::quantile, 0.95))
  obs <- problem$field$y[held_out]
  draws <- posterior::subset_draws(posterior::as_draws(fit), variable = rownames(s))
  sampler <- attr(check_convergence(fit, warn = FALSE), "sampler")
  data.frame(problem = k, kernel = kernel, parameter = rownames(s), mean = s$mean, sd = s$sd,
             mcse = posterior::summarise_draws(draws, "mcse_mean")$mcse_mean,
             covered = s$q5 <= truth & truth <= s$q95,
             width = mean(pred$q95 - pred$q5),
             held_out_covered = mean(pred$q5 <= obs & obs <= pred$q95),
             rhat = max(s$rhat), divergent = sampler$divergent, seconds = seconds,
             ess_per_s = min(s$ess_bulk) / seconds)
}

rows <- list()
for (k in if (hourly) span else seq(span[1], span[length(span)])) {
  problem <- if (hourly) hourly_problem(k) else bayesbem:::synthetic_problem(days, 30, k)
  for (kernel in c("product", "additive")) {
    row <- one_fit(problem, kernel, k)
    print(row, digits = 3, row.names = FALSE)
    rows[[length(rows) + 1L]] <- row
  }
}
out <- do.call(rbind, rows)
product <- out[out$kernel == "product", ]
additive <- out[out$kernel == "additive", ]
cat("\nAdditive against product, per problem and parameter:\n")
print(data.frame(problem = product$problem, parameter = product$parameter,
                 mean_difference_in_mcse = (additive$mean - product$mean) /
                   sqrt(additive$mcse^2 + product$mcse^2),
                 mean_difference_in_sd = (additive$mean - product$mean) / product$sd,
                 sd_ratio = additive$sd / product$sd), digits = 3, row.names = FALSE)
cat("\nPer kernel:\n")
print(do.call(rbind, lapply(split(out, out$kernel), function(s) {
  data.frame(kernel = s$kernel[1], truth_covered = sprintf("%d/%d", sum(s$covered), nrow(s)),
             held_out_width = mean(s$width[!duplicated(s$problem)]),
             held_out_covered = mean(s$held_out_covered[!duplicated(s$problem)]),
             max_rhat = max(s$rhat), divergent = sum(s$divergent[!duplicated(s$problem)]),
             seconds = mean(s$seconds[!duplicated(s$problem)]),
             min_ess_per_s = min(s$ess_per_s))
})), digits = 3, row.names = FALSE)
cat(sprintf("machine: %d cores; R %s; rstan %s; %s\n", parallel::detectCores(), getRversion(),
            packageVersion("rstan"), Sys.Date()))
