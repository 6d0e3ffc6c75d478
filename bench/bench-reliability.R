# Benchmark (issue 14): does calibrate() with its default settings converge
# and cover the truth at every data size? For each size (n field periods, mt
# simulation runs): synthetic problems from the embedded model made by the
# internal bayesbem:::synthetic_problem() (monthly weather for n <= 36: 2012,
# 2013 and a perturbed copy of 2013; daily weather of 2013, n days evenly
# spaced, above), the paper's three calibration parameters with the truth
# drawn uniformly within the middle 80 % of their ranges, noise 2 % of the
# mean output, a correct simulator, a maximin LHS design of mt runs at every
# field period. Each problem is fitted with
# calibrate(field, runs, seed = ...) and nothing else, plus the arguments in
# BENCH_CALIBRATE (an R expression giving a list, e.g.
# 'list(emulator_mean = "zero")' for the paper's model), and on the parameter
# scales in BENCH_SCALES (koh_data()'s `scales`, "auto" by default).
# Reported per size: share converged (max R-hat < 1.01 over every
# parameter, no divergent transition, bulk and tail ESS >= 400), coverage of
# the truth by the 90 % intervals of each calibration parameter, the share
# whose calibration parameters alone pass the same R-hat and ESS rule
# (`tf_converged`: the chains may still disagree on the emulator's
# hyperparameters), median wall time, the worst R-hat's variable, the mean
# leapfrog steps per sampling and per warm-up iteration and the chains'
# summed seconds (stage 2 of a modular fit), how many of a modular fit's 16
# stage-1 searches reached the emulator's mode (`stage1_found`), the
# parameters put on a log or reciprocal scale, and the check of the
# emulator by validate_emulator() on the problem's simulator at 20 draws:
# each parameter's `shift` and the posterior mean's distance from the truth
# (`bias_sd`), both in posterior sds, the shift over the sd the emulator's
# stated error explains (`shift_z`), the verdict (`emulator_trusted`), its
# per-period part (`emulator_coverage`, `rmse_over_noise`), and the coverage
# of the fits it trusted (`coverage_trusted`).
# With BENCH_REFINE=r (r > 0) each problem is then refined once, as the
# verdict of validate_emulator() advises: r runs from design_posterior() on
# the first fit, added to the mt runs, and a second fit, reported as size
# (n, mt + r) with its wall time (both fits and the runs).
# With BENCH_CSV=<file>, each problem's row is also appended to that CSV file
# (so that runs over several sessions can be pooled); with BENCH_SAVE=<dir>
# each fit is saved there as fit-<n>-<mt>-<problem>.rds.
# Usage, from the package root, with bayesbem installed:
#   [BENCH_CALIBRATE='list(...)'] [BENCH_SCALES=identity] [BENCH_REFINE=r] [BENCH_CSV=file] [BENCH_SAVE=dir] \
#   Rscript bench/bench-reliability.R \
#     [sizes as n:mt:problems, comma-separated; default 12:10:10,12:30:10,36:30:10,120:30:3,365:30:3]
# `problems` is a count (problems 1 to k) or a range k1-k2 (e.g. 365:30:2-3).
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE, width = 250)
args <- commandArgs(trailingOnly = TRUE)
spec <- if (length(args) > 0) args[1] else "12:10:10,12:30:10,36:30:10,120:30:3,365:30:3"
sizes <- do.call(rbind, lapply(strsplit(strsplit(spec, ",")[[1]], ":"), function(s) {
  k <- as.integer(strsplit(s[3], "-")[[1]])
  data.frame(n = as.integer(s[1]), mt = as.integer(s[2]), first = if (length(k) > 1) k[1] else 1L,
             last = k[length(k)])
}))
extra <- eval(parse(text = Sys.getenv("BENCH_CALIBRATE", "list()")))
scales <- Sys.getenv("BENCH_SCALES", "auto")

refine <- as.integer(Sys.getenv("BENCH_REFINE", "0"))

fit_problem <- function(problem, runs, k) {
  data <- koh_data(problem$field, runs, scales = scales)
  suppressWarnings(do.call(calibrate, c(list(data, seed = 4000 + k), extra)),
                   classes = "bayesbem_warning_convergence")
}

# The default fit's row and, with BENCH_REFINE, the refined fit's.
one_problem <- function(n, mt, k) {
  problem <- bayesbem:::synthetic_problem(n, mt, k)
  wall <- system.time(fit <- fit_problem(problem, problem$runs, k))[["elapsed"]]
  save_dir <- Sys.getenv("BENCH_SAVE")
  if (nzchar(save_dir)) saveRDS(fit, file.path(save_dir, sprintf("fit-%d-%d-%d.rds", n, mt, k)))
  first <- evaluate(fit, problem, n, mt, k, wall)
  if (refine == 0L) {
    return(first)
  }
  wall2 <- system.time({
    added <- simulate_design(problem$simulator, design_posterior(fit, refine, seed = 5000 + k))
    refit <- fit_problem(problem, rbind(problem$runs, added), k)
  })[["elapsed"]]
  rbind(first, evaluate(refit, problem, n, mt + refine, k, wall + wall2))
}

# Mean leapfrog steps per iteration of the fit's (stage-2) chains, in
# `phase` ("warmup" or "sampling"; NaN when warm-up was not saved).
leapfrog_steps <- function(fit, phase) {
  all <- fit$sampler$params
  kept <- bayesbem:::sampler_params(fit)
  steps <- Map(function(a, k) {
    warm <- seq_len(nrow(a) - nrow(k))
    if (phase == "sampling") k[, "n_leapfrog__"] else a[warm, "n_leapfrog__"]
  }, all, kept)
  round(mean(unlist(steps)), 1)
}

evaluate <- function(fit, problem, n, mt, k, wall) {
  truth <- problem$truth
  conv <- check_convergence(fit, warn = FALSE)
  sampler <- attr(conv, "sampler")
  draws <- bayesbem:::parameter_draws(fit)
  covered <- vapply(names(truth), function(p) {
    q <- stats::quantile(draws[, p], c(0.05, 0.95))
    truth[[p]] >= q[1] && truth[[p]] <= q[2]
  }, logical(1))
  worst <- which.max(conv$rhat)
  check <- validate_emulator(fit, problem$simulator, ndraws = 20)
  # the R-hat and ESS rule over the table's rows `rows`
  passes <- function(rows) all(conv$rhat[rows] < 1.01 & pmin(conv$ess_bulk, conv$ess_tail)[rows] >= 400)
  data.frame(n = n, mt = mt, problem = k,
             converged = passes(TRUE) && sampler$divergent == 0,
             max_rhat = max(conv$rhat), worst = conv$variable[worst],
             # the calibration parameters alone
             tf_converged = passes(conv$variable %in% names(truth)),
             min_ess = min(conv$ess_bulk, conv$ess_tail), divergent = sampler$divergent,
             treedepth_hits = sampler$treedepth_hits,
             # mean leapfrog steps per sampling and per warm-up iteration, and
             # the chains' seconds summed (stage 2 of a modular fit; a chain
             # restarted from a lone main mode counts its second run only)
             leapfrog = leapfrog_steps(fit, "sampling"),
             warmup_leapfrog = leapfrog_steps(fit, "warmup"),
             chain_s = round(sum(fit$sampler$elapsed)),
             dropped = paste(unlist(fit$settings$dropped), collapse = " "),
             # how many of stage 1's searches reached the emulator's mode
             stage1_found = if (is.null(fit$emulator)) NA else
               bayesbem:::searches_at_mode(fit$emulator$searches),
             # parameters koh_data(scales = "auto") took off the identity
             scales = paste(names(Filter(function(s) s != "identity", fit$data$scaling$t_scale)),
                            collapse = " "),
             covered = sum(covered),
             missed = paste(names(truth)[!covered], collapse = " "),
             # how far each parameter's posterior mean lies from the truth,
             # and how far validate_emulator() says the emulator's error
             # moved it (both in posterior sds), and its verdict
             bias_sd = paste(sprintf("%.2f", (colMeans(draws) - unlist(truth)) /
                                       apply(draws, 2, stats::sd)), collapse = " "),
             shift = paste(sprintf("%.2f", check$shift$shift), collapse = " "),
             # the shifts over the sd the emulator's stated error explains
             shift_z = paste(sprintf("%.1f", check$shift$z), collapse = " "),
             emulator_trusted = check$trusted,
             # the verdict's per-period part: the share of the simulator's
             # outputs inside the emulator's 90 % intervals, RMSE / noise sd
             emulator_coverage = round(check$coverage, 2),
             rmse_over_noise = round(check$rmse / check$noise_sd, 2),
             parameters = length(covered), wall_s = wall)
}

cat(sprintf("machine: %s, %d cores; R %s; date %s\ncalibrate() extra arguments: %s; scales: %s\n\n",
            Sys.info()[["nodename"]], parallel::detectCores(), getRversion(), Sys.Date(),
            Sys.getenv("BENCH_CALIBRATE", "none"), scales))
rows <- list()
for (i in seq_len(nrow(sizes))) {
  s <- sizes[i, ]
  for (k in seq(s$first, s$last)) {
    r <- one_problem(s$n, s$mt, k)
    print(r, row.names = FALSE)
    csv <- Sys.getenv("BENCH_CSV")
    if (nzchar(csv)) {
      utils::write.table(r, csv, sep = ",", row.names = FALSE, col.names = !file.exists(csv),
                         append = file.exists(csv))
    }
    rows[[length(rows) + 1L]] <- r
  }
}
all <- do.call(rbind, rows)
summary <- do.call(rbind, lapply(split(all, list(all$n, all$mt), drop = TRUE), function(d) {
  data.frame(n = d$n[1], mt = d$mt[1], problems = nrow(d),
             converged = sprintf("%d/%d", sum(d$converged), nrow(d)),
             tf_converged = sprintf("%d/%d", sum(d$tf_converged), nrow(d)),
             coverage_90 = sprintf("%d/%d", sum(d$covered), sum(d$parameters)),
             emulator_trusted = sprintf("%d/%d", sum(d$emulator_trusted), nrow(d)),
             coverage_trusted = sprintf("%d/%d", sum(d$covered[d$emulator_trusted]),
                                        sum(d$parameters[d$emulator_trusted])),
             median_wall_s = round(stats::median(d$wall_s)),
             max_rhat = round(max(d$max_rhat), 3))
}))
cat("\nSummary\n")
print(summary[order(summary$n, summary$mt), ], row.names = FALSE)
