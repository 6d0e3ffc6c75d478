# Benchmark: savings against a known truth. Each problem: a simulator on
# the 2013 weather (the embedded model, or the shipped EnergyPlus model)
# with true parameter values drawn within their ranges, a hidden effect the
# model lacks (a load in humid months) and noise make twelve pre-retrofit
# bills; 20 runs; calibrate() with its defaults; then savings() of a
# retrofit (equipment power density x 0.7) under the 2012 weather (the
# reporting year), with the default discrepancy assumption. The true
# savings are the simulator's at the true values, baseline less retrofit,
# under the same weather (the hidden effect, untouched by the retrofit,
# cancels). Reported: whether the 90 % interval of the total holds the
# truth, the error of the point estimate, and the interval's half-width
# beside Guideline 14's Annex B formula (from avoided_energy() with the
# retrofit's measured use).
# Target (issue 42): coverage 85-95 % over at least 20 problems.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-savings.R [problems] [embedded|eplus]
#   problems: a count (1 to k) or a range k1-k2; default 20, embedded.
#   eplus needs BAYESBEM_EPLUS; BENCH_DRAWS: posterior draws (default 40);
#   BENCH_CACHE: a directory for cached simulator runs (a rerun resumes);
#   BENCH_WORKERS: simulator runs in parallel (multisession; default 1).
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
spec <- as.integer(strsplit(if (length(args) > 0L) args[1] else "20", "-")[[1]])
problems <- if (length(spec) > 1L) seq(spec[1], spec[2]) else seq_len(spec)
kind <- if (length(args) > 1L) args[2] else "embedded"
ndraws <- as.integer(Sys.getenv("BENCH_DRAWS", "40"))
cache <- if (nzchar(Sys.getenv("BENCH_CACHE"))) Sys.getenv("BENCH_CACHE") else NULL
workers <- as.integer(Sys.getenv("BENCH_WORKERS", "1"))
if (workers > 1L) future::plan(future::multisession, workers = workers)
epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
make_simulator <- function(year) {
  if (kind == "eplus") eplus_simulator(weather = epw(year)) else bem_simulator(epw(year))
}
params <- c("equipment_power_density", "infiltration_per_exterior_area")
pre <- make_simulator(2013)
post <- make_simulator(2012)
# the retrofit scales equipment power density by 0.7: the reporting-year
# simulator runs it below the design range's floor too (both simulators
# are valid there), so that a low posterior draw can be retrofitted
floor <- post$parameters$parameter == "equipment_power_density"
post$parameters$min[floor] <- 0.7 * post$parameters$min[floor]
ranges <- pre$parameters[pre$parameters$parameter %in% params, ]
retrofit_scale <- c(equipment_power_density = 0.7)

one_problem <- function(k) {
  set.seed(1000 + k)
  truth <- as.list(stats::setNames(stats::runif(2, ranges$min + 0.2 * (ranges$max - ranges$min),
                                                ranges$max - 0.2 * (ranges$max - ranges$min)),
                                   ranges$parameter))
  field <- simulate_field(pre, truth, effect = function(d) 120 * (d$rh > 47), noise_sd = 25,
                          seed = k)
  runs <- simulate_design(pre, design_lhs(ranges, n = 20, seed = k), cache_dir = cache)
  start <- proc.time()[["elapsed"]]
  fit <- suppressWarnings(calibrate(field[c("y", "temp", "rh", "solar")], runs, seed = k,
                                    cores = 2, refresh = 0),
                          classes = "bayesbem_warning_convergence")
  s <- suppressWarnings(savings(fit, post, scenario(post, scale = retrofit_scale),
                                ndraws = ndraws, cache_dir = cache),
                        classes = "bayesbem_warning_extrapolation")
  total <- summary(s)[13, ]
  after <- truth
  after$equipment_power_density <- after$equipment_power_density * 0.7
  true_savings <- sum(simulate_field(post, truth)$y - simulate_field(post, after)$y)
  measured_after <- simulate_field(post, after, effect = function(d) 120 * (d$rh > 47),
                                   noise_sd = 25, seed = 100 + k)$y
  a <- suppressWarnings(avoided_energy(fit, post, measured_after, ndraws = ndraws,
                                      cache_dir = cache),
                        classes = "bayesbem_warning_extrapolation")
  data.frame(simulator = kind, problem = k, truth = true_savings, estimate = total$savings,
             lower = total$lower, upper = total$upper,
             covered = true_savings >= total$lower && true_savings <= total$upper,
             error_pct = 100 * (total$savings - true_savings) / true_savings,
             fsu_bayes = a$fsu$fsu[1], fsu_g14 = a$fsu$fsu[2],
             seconds = proc.time()[["elapsed"]] - start)
}

rows <- list()
for (k in problems) {
  rows[[length(rows) + 1L]] <- one_problem(k)
  out <- do.call(rbind, rows)
  num <- vapply(out, is.double, logical(1))
  out[num] <- lapply(out[num], signif, 3)
  print(out[nrow(out), ], row.names = FALSE)
}
out <- do.call(rbind, rows)
cat(sprintf("\ncovered %d of %d (%.0f %%); median |error| %.1f %%; median FSU %.1f %% (Guideline 14's formula %.1f %%)\n",
            sum(out$covered), nrow(out), 100 * mean(out$covered), stats::median(abs(out$error_pct)),
            100 * stats::median(out$fsu_bayes), 100 * stats::median(out$fsu_g14)))
cat(sprintf("machine: %d cores; R %s; %s\n", parallel::detectCores(), getRversion(), Sys.Date()))
