# Benchmark (issue 55, time): a year of hourly data calibrated to
# convergence with the public API. The embedded hourly model on the 2013
# weather (inputs temp, rh, solar, weekday, daytype_hour), three
# parameters (equipment power density, infiltration, cooling setpoint) at
# the middle of their ranges, the simulator's use there plus AR(1) noise
# (phi 0.7, sd 0.5 kWh; or white, sd 0.5), the first `hours` hours with
# their times; `runs` LHS runs;
# calibrate()'s defaults (the additive discrepancy at this size) with
# `chains` chains on every core, white or AR(1) noise. Reported per fit:
# wall time (the data; the fit, both stages), max R-hat, divergent
# transitions, mean leapfrog steps per draw, draws at the maximum tree
# depth, min bulk ESS, the truth inside the 90 % intervals, the posterior
# mean of phi, and the months whose measured total lies inside the 90 %
# predictive interval of its total (200 draws with noise); then the time
# of explain_discrepancy() with the calendar (`weekend`, and by hour
# `hour`) and what it names (the truth: nothing). With "daily": the embedded model by day on 2012,
# 2013 and 2012 again (a third year of the same weather, `year` an
# input), 1,097 days.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-year-hours.R [hours] [runs, comma-separated] [chains] [none|ar1|auto] [ar1|white]
#   Rscript bench/bench-year-hours.R daily [runs] [chains] [none|ar1|auto] [ar1|white]
# (the 4th argument is the fit's noise, the 5th the truth's).
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
daily <- length(args) > 0L && args[1] == "daily"
arg <- function(i, default) if (length(args) >= i) args[i] else default
hours <- if (daily) NA else as.integer(arg(1, "8760"))
runs_list <- as.integer(strsplit(arg(2, "30"), ",")[[1]])
chains <- as.integer(arg(3, "4"))
correlation <- arg(4, "ar1")
truth_noise <- arg(5, "ar1")

weather <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
params <- c("equipment_power_density", "infiltration_per_exterior_area", "cooling_setpoint")

# The problem: the simulator's rows and times, its use at the truth with
# AR(1) noise, and a function giving the runs' table for a design.
problem <- if (daily) {
  years <- c(2012, 2013, 2012)
  sims <- lapply(years, function(y) bem_simulator(weather(y), by = "day"))
  x <- do.call(rbind, Map(function(s, k) cbind(s$x, year = k), sims, seq_along(sims)))
  times <- as.Date("2012-01-01") + seq_len(nrow(x)) - 1
  simulate_rows <- function(design) {
    do.call(rbind, Map(function(s, k) {
      out <- simulate_design(s, design)
      out$year <- k
      out
    }, sims, seq_along(sims)))
  }
  list(x = x, times = times, parameters = sims[[1]]$parameters, simulate = simulate_rows,
       calendar = do.call(rbind, lapply(sims, calendar_covariates))["weekend"])
} else {
  sim <- bem_simulator(weather(2013), by = "hour")
  keep <- seq_len(hours)
  list(x = sim$x[keep, ], times = sim$periods$start[keep], parameters = sim$parameters,
       calendar = calendar_covariates(sim)[keep, c("hour", "weekend")],
       simulate = function(design) {
         out <- simulate_design(sim, design)
         out[rep((seq_len(nrow(design)) - 1L) * nrow(sim$x), each = hours) + keep, ]
       })
}
ranges <- problem$parameters[problem$parameters$parameter %in% params, ]
truth <- stats::setNames(as.list((ranges$min + ranges$max) / 2), ranges$parameter)
set.seed(55)
use <- problem$simulate(as.data.frame(truth))$eta
phi_true <- if (truth_noise == "ar1") 0.7 else 0
noise <- 0.5 * as.numeric(stats::filter(stats::rnorm(length(use), sd = sqrt(1 - phi_true^2)), phi_true,
                                         method = "recursive", init = stats::rnorm(1)))
field <- data.frame(y = use + noise, problem$x, time = problem$times, row.names = NULL)

rows <- lapply(runs_list, function(mt) {
  runs <- problem$simulate(design_lhs(ranges, n = mt, seed = 2))
  t0 <- Sys.time()
  d <- suppressMessages(koh_data(field, runs))
  t1 <- Sys.time()
  fit <- calibrate(d, noise_correlation = correlation, chains = chains, seed = 1)
  t2 <- Sys.time()
  conv <- check_convergence(fit, warn = FALSE)
  draws <- posterior::as_draws_df(fit)
  covered <- vapply(names(truth), function(v) {
    q <- stats::quantile(draws[[v]], c(0.05, 0.95))
    truth[[v]] >= q[1] && truth[[v]] <= q[2]
  }, logical(1))
  sampler <- do.call(rbind, bayesbem:::sampler_params(fit))
  predicted <- predict(fit, noise = TRUE, ndraws = 200, summary = FALSE)
  month <- format(field$time, "%Y-%m")
  months_covered <- vapply(split(seq_along(month), month), function(i) {
    q <- stats::quantile(rowSums(predicted[, i, drop = FALSE]), c(0.05, 0.95))
    sum(field$y[i]) >= q[1] && sum(field$y[i]) <= q[2]
  }, logical(1))
  t3 <- Sys.time()
  explained <- explain_discrepancy(fit, problem$calendar, seed = 1)
  t4 <- Sys.time()
  data.frame(rows = d$n, runs = mt, truth_noise = truth_noise, noise = fit$settings$noise_correlation,
             chains = chains,
             data_s = as.numeric(difftime(t1, t0, units = "secs")),
             fit_s = as.numeric(difftime(t2, t1, units = "secs")),
             max_rhat = max(conv$rhat, na.rm = TRUE), divergent = sum(sampler[, "divergent__"]),
             leapfrog = mean(sampler[, "n_leapfrog__"]),
             treedepth_hits = bayesbem:::fit_sampler_diagnostics(fit)$treedepth_hits,
             min_bulk_ess = min(conv$ess_bulk, na.rm = TRUE),
             covered = sprintf("%d/%d", sum(covered), length(covered)),
             phi = if (identical(fit$settings$noise_correlation, "ar1")) mean(draws$phi) else NA,
             months_covered = sprintf("%d/%d", sum(months_covered), length(months_covered)),
             explain_s = as.numeric(difftime(t4, t3, units = "secs")),
             named = c(explained$candidate[explained$explains], "nothing")[1])
})
out <- do.call(rbind, rows)
print(out, digits = 3, row.names = FALSE)
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\n", Sys.info()[["nodename"]],
            parallel::detectCores(), getRversion(), packageVersion("rstan"), Sys.Date()))
