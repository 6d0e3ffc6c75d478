# Benchmark (issue 14, speed): time per gradient of the log density of the
# joint grid program (koh_grid.stan), and of the two stages of the modular
# fit (koh_emulator.stan on at most 60 grid inputs; koh_modular.stan with the
# emulator fixed), for n daily field periods of 2013 and mt runs of the
# embedded model (the paper's three calibration parameters, LHS design),
# with the default priors (linear emulator mean). Mean of repeated
# rstan::grad_log_prob() calls at one point; one core. The grid and stage-2
# programs are timed with their n x n factor by Eigen and by R's LAPACK (on
# the BLAS printed at the end; use_lapack() picks one of the two in fits).
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-gradient.R [n values, comma-separated] [mt]
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
ns <- if (length(args) > 0) as.integer(strsplit(args[1], ",")[[1]]) else c(36, 120, 365)
mt <- if (length(args) > 1) as.integer(args[2]) else 30L

# Mean time of one rstan::grad_log_prob() call over about a second of
# repeated calls (one call is below the timer's 1 ms resolution at small n).
grad_time <- function(model, data, seconds = 1) {
  utils::capture.output(fit0 <- rstan::sampling(model, data = data, chains = 0))
  upars <- rep(0.1, rstan::get_num_upars(fit0))
  one <- system.time(rstan::grad_log_prob(fit0, upars))[["elapsed"]]
  reps <- max(3L, ceiling(seconds / max(one, 1e-3)))
  system.time(for (i in seq_len(reps)) rstan::grad_log_prob(fit0, upars))[["elapsed"]] / reps
}

# ms per gradient of `program` on `data`, its factor by Eigen (0) or LAPACK (1)
ms <- function(program, data, lapack) {
  1000 * grad_time(bayesbem:::stanmodels[[program]], utils::modifyList(data, list(lapack = lapack)))
}

daily <- epw_daily(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
truth <- list(fan_total_efficiency = 0.5, equipment_power_density = 15,
              infiltration_per_exterior_area = 0.0008)
priors <- koh_priors()
rows <- list()
for (n in ns) {
  sim <- bem_simulator(daily[unique(round(seq(1, nrow(daily), length.out = n))), ])
  field <- simulate_field(sim, truth, noise_sd = 1, seed = 1)
  params <- sim$parameters[sim$parameters$parameter %in% names(truth), ]
  d <- koh_data(field, simulate_design(sim, design_lhs(params, n = mt, seed = 2)))
  grid <- bayesbem:::koh_stan_data(d, priors, structure = "grid")
  stage1 <- bayesbem:::emulator_stan_data(d, priors)
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1, b = rep(0, grid$n_b))
  stage2 <- bayesbem:::modular_stan_data(d, priors, emulator)
  rows[[length(rows) + 1L]] <- data.frame(
    n = n, mt = mt,
    joint_grid_ms = ms("koh_grid", grid, 0L), joint_grid_lapack_ms = ms("koh_grid", grid, 1L),
    stage1_ms = 1000 * grad_time(bayesbem:::stanmodels$koh_emulator, stage1),
    stage2_ms = ms("koh_modular", stage2, 0L), stage2_lapack_ms = ms("koh_modular", stage2, 1L)
  )
  print(rows[[length(rows)]], digits = 3, row.names = FALSE)
}
cat("\nTime per gradient (ms):\n")
print(do.call(rbind, rows), digits = 3, row.names = FALSE)
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\nBLAS: %s (use_lapack(): %s)\n",
            Sys.info()[["nodename"]], parallel::detectCores(), getRversion(),
            packageVersion("rstan"), Sys.Date(), extSoftVersion()[["BLAS"]],
            bayesbem:::use_lapack()))
