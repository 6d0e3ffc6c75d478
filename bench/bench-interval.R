# Benchmark: smart-meter data end to end, known truth. Each problem: a
# simulator by hour on the 2013 weather (the embedded hourly model, or the
# case-study EnergyPlus model), two parameters drawn in the middle 80 % of
# their ranges, the simulator's hourly use there as 15-minute readings in
# Denver's local time stamped at each interval's end, plus noise (sd 2 %
# of the mean reading); field_hours() brings them to the simulator's hours
# (BENCH_DAYS days from 7 March, default 7: across the change to
# daylight-saving time on the 10th); 15 runs, the runs' rows at the
# meter's hours; calibrate()'s defaults. Reported: the 90 % intervals
# holding the truth, convergence, the fit's wall time
# (bench/results/interval.md; a year of hours: bench-year-hours.R).
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-interval.R [problems] [embedded|eplus]  (default 3 embedded)
#   eplus needs BAYESBEM_EPLUS; BENCH_CACHE: a directory for cached runs.
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
problems <- seq_len(if (length(args) > 0L) as.integer(args[1]) else 3L)
kind <- if (length(args) > 1L) args[2] else "embedded"
cache <- if (nzchar(Sys.getenv("BENCH_CACHE"))) Sys.getenv("BENCH_CACHE") else NULL
epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
sim <- if (kind == "eplus") eplus_simulator(weather = epw, by = "hour") else
  bem_simulator(epw, by = "hour")
params <- c("equipment_power_density", "infiltration_per_exterior_area")
ranges <- sim$parameters[sim$parameters$parameter %in% params, ]
days <- as.integer(Sys.getenv("BENCH_DAYS", "7"))
time <- as.POSIXct("2013-03-07 00:15", tz = "America/Denver") + 900 * (0:(4 * 24 * days - 1))
hour <- floor(as.numeric(difftime(time - 900, sim$periods$start[1], units = "hours"))) + 1

rows <- lapply(problems, function(k) {
  set.seed(3000 + k)
  truth <- as.list(stats::setNames(stats::runif(2, ranges$min + 0.2 * (ranges$max - ranges$min),
                                                ranges$max - 0.2 * (ranges$max - ranges$min)),
                                   ranges$parameter))
  use <- simulate_design(sim, as.data.frame(truth), cache_dir = cache)$eta
  readings <- use[hour] / 4
  readings <- readings + stats::rnorm(length(readings), 0, 0.02 * mean(readings))
  field <- field_hours(sim, time, readings, stamps = "end")
  at <- match(field$time, sim$periods$start)
  runs <- simulate_design(sim, design_lhs(ranges, n = 15, seed = k), cache_dir = cache)
  runs <- runs[rep(seq_len(nrow(sim$x)), 15) %in% at, ]
  start <- proc.time()[["elapsed"]]
  fit <- suppressWarnings(calibrate(field, runs, seed = k, refresh = 0),
                          classes = "bayesbem_warning_convergence")
  wall <- proc.time()[["elapsed"]] - start
  draws <- posterior::as_draws_matrix(fit)
  covered <- vapply(params, function(p) {
    q <- stats::quantile(draws[, p], c(0.05, 0.95))
    truth[[p]] >= q[1] && truth[[p]] <= q[2]
  }, logical(1))
  conv <- check_convergence(fit, warn = FALSE)
  cat(sprintf("problem %d: %d hours, %d/2 covered, %.0f s\n", k, nrow(field), sum(covered), wall))
  data.frame(problem = k, hours = nrow(field), covered = sum(covered),
             converged = all(conv$ok) && sum(attr(conv, "sampler")$divergent) == 0, wall = wall)
})
out <- do.call(rbind, rows)
cat(sprintf("\n%s by hour: %d problems of %d hours; converged %d/%d; covered %d/%d; median wall %.0f s\n",
            kind, nrow(out), out$hours[1], sum(out$converged), nrow(out), sum(out$covered),
            2 * nrow(out), stats::median(out$wall)))
cat(sprintf("machine: %d cores; R %s; %s\n", parallel::detectCores(), getRversion(), Sys.Date()))
