# Benchmark (issue 14, speed): time per gradient of the log density of the
# joint grid likelihood (koh.stan), and of the two stages of the modular
# fit (stage 1 on at most 60 grid inputs; stage 2 with the emulator fixed), for n daily field periods of 2013 and mt runs of the
# embedded model (the paper's three calibration parameters, LHS design),
# with the default priors (linear emulator mean). Mean of repeated
# rstan::grad_log_prob() calls at one point; one core. The grid and stage-2
# likelihoods are timed with their n x n factor by Eigen and by R's LAPACK (on
# the BLAS printed at the end; use_lapack() picks one of the two in fits).
# With "hourly" (issue 55): stage 2 with the basis emulator
# (koh_basis.stan) as the rows grow to a year of hours, the discrepancy's
# product kernel (its n x n factor, up to `max_product` rows) beside the
# additive Hilbert-space one (R/gp-hsgp.R), the latter with white and with
# AR(1) noise: the embedded hourly model on the 2013 weather (inputs temp,
# rh, solar, weekday, daytype_hour), the first n hours, 30 runs (LHS of
# equipment power density, infiltration and the cooling setpoint), and the
# set-up (the basis's SVD, the Gram matrices).
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-gradient.R [n values, comma-separated] [mt]
#   Rscript bench/bench-gradient.R hourly [n values] [max_product]
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
hourly <- length(args) > 0 && args[1] == "hourly"
if (hourly) args <- args[-1]
ns <- if (length(args) > 0) as.integer(strsplit(args[1], ",")[[1]]) else
  if (hourly) c(730, 2190, 4380, 8760) else c(36, 120, 365)
mt <- if (length(args) > 1 && !hourly) as.integer(args[2]) else 30L
max_product <- if (length(args) > 1 && hourly) as.integer(args[2]) else 2190L

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

machine <- function() {
  cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\nBLAS: %s (use_lapack(): %s)\n",
              Sys.info()[["nodename"]], parallel::detectCores(), getRversion(),
              packageVersion("rstan"), Sys.Date(), extSoftVersion()[["BLAS"]],
              bayesbem:::use_lapack()))
}

if (hourly) {
  sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"), by = "hour")
  params <- sim$parameters[sim$parameters$parameter %in%
                             c("equipment_power_density", "infiltration_per_exterior_area",
                               "cooling_setpoint"), ]
  truth <- stats::setNames(as.list((params$min + params$max) / 2), params$parameter)
  field <- simulate_field(sim, truth, noise_sd = 0.5, seed = 1)
  field$time <- sim$periods$start
  runs <- simulate_design(sim, design_lhs(params, n = mt, seed = 2))
  hours <- nrow(sim$x)
  priors <- koh_priors()
  rows <- list()
  for (n in ns) {
    keep <- seq_len(n)
    d <- suppressMessages(koh_data(field[keep, ], runs[rep((seq_len(mt) - 1L) * hours, each = n) + keep, ]))
    setup <- system.time({
      basis <- bayesbem:::basis_emulator(d)
      emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                       b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))), basis = basis)
      additive <- bayesbem:::basis_stan_data(d, priors, emulator, bayesbem:::hsgp_design())
    })[["elapsed"]]
    product <- if (n <= max_product) {
      1000 * grad_time(bayesbem:::stanmodels$koh_basis, bayesbem:::basis_stan_data(d, priors, emulator))
    } else {
      NA
    }
    rows[[length(rows) + 1L]] <- data.frame(
      n = n, components = ncol(basis$B), basis_functions = additive$m * d$p, setup_s = setup,
      additive_ms = 1000 * grad_time(bayesbem:::stanmodels$koh_basis, additive),
      additive_ar1_ms = 1000 * grad_time(bayesbem:::stanmodels$koh_basis, bayesbem:::basis_stan_data(
        d, priors, emulator, bayesbem:::hsgp_design(), bayesbem:::output_segments(d))),
      product_ms = product)
    print(rows[[length(rows)]], digits = 3, row.names = FALSE)
  }
  out <- do.call(rbind, rows)
  cat("\nms per gradient, stage 2 with the basis emulator:\n")
  print(out, digits = 3, row.names = FALSE)
  cat(sprintf("additive, largest / smallest n: %.2f (rows %.0f x)\n",
              out$additive_ms[nrow(out)] / out$additive_ms[1], out$n[nrow(out)] / out$n[1]))
  machine()
  quit(save = "no")
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
    joint_grid_ms = ms("koh", grid, 0L), joint_grid_lapack_ms = ms("koh", grid, 1L),
    stage1_ms = 1000 * grad_time(bayesbem:::stanmodels$koh, stage1),
    stage2_ms = ms("koh", stage2, 0L), stage2_lapack_ms = ms("koh", stage2, 1L)
  )
  print(rows[[length(rows)]], digits = 3, row.names = FALSE)
}
cat("\nTime per gradient (ms):\n")
print(do.call(rbind, rows), digits = 3, row.names = FALSE)
machine()
