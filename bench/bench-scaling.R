# Benchmark (issue 7): how the grid and dense likelihoods scale with the
# number of field periods n and of simulation runs mt. Synthetic data from
# the embedded model driven by daily weather (n days of 2013, evenly
# spaced), the paper's three calibration parameters, a Latin-hypercube design of mt runs
# at every field period. For each size: time per gradient of both programs
# (rstan::grad_log_prob, median of repeats), and the wall time, max R-hat
# and min bulk ESS of a 4-chain, 1000-iteration grid fit on 2 cores. Dense
# fits are run only where the per-gradient time makes them finish within
# 30 minutes; elsewhere the table gives the estimated time (gradients used
# by the grid fit x dense time per gradient) and says "skipped".
# Usage, from the package root, with bayesbem installed:
#   [BENCH_FIT_MAX_N=120] Rscript bench/bench-scaling.R [n values, comma-separated] [mt values]
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
ns <- if (length(args) > 0) as.integer(strsplit(args[1], ",")[[1]]) else c(12, 48, 120, 365)
mts <- if (length(args) > 1) as.integer(strsplit(args[2], ",")[[1]]) else c(10, 30)

daily_weather <- function(epw, n) {
  h <- bayesbem:::read_epw_hourly(epw)
  day <- (seq_len(nrow(h)) - 1L) %/% 24L + 1L
  means <- lapply(c("temp", "rh", "dni", "dhi", "ghi"), function(v) tapply(h[[v]], day, mean))
  w <- data.frame(month = tapply(h$month, day, `[`, 1), days = 1, hours = 24,
                  stats::setNames(means, c("temp", "rh", "dni", "dhi", "ghi")))
  w[unique(round(seq(1, nrow(w), length.out = n))), ]
}

grad_time <- function(model, data, reps) {
  utils::capture.output(fit0 <- rstan::sampling(model, data = data, chains = 0))
  upars <- rep(0.1, rstan::get_num_upars(fit0))
  t <- vapply(seq_len(reps), function(i) {
    system.time(rstan::grad_log_prob(fit0, upars))[["elapsed"]]
  }, numeric(1))
  stats::median(t)
}

epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
# the paper's three calibration parameters (lighting and equipment power
# densities together would leave a ridge that no sampler mixes along)
truth <- list(fan_total_efficiency = 0.5, equipment_power_density = 15,
              infiltration_per_exterior_area = 0.0008)
N_dense_max <- 4100
dense_ref <- NULL
# grid fits are run up to this many field periods (environment variable
# BENCH_FIT_MAX_N); larger sizes get their time per gradient only
fit_max_n <- as.integer(Sys.getenv("BENCH_FIT_MAX_N", "365"))
grads_ref <- list()
rows <- list()
for (n in ns) {
  sim <- bem_simulator(daily_weather(epw, n))
  field <- simulate_field(sim, truth, noise_sd = 0.5, seed = 1)
  params <- sim$parameters[sim$parameters$parameter %in% names(truth), ]
  for (mt in mts) {
    runs <- simulate_design(sim, design_lhs(params, n = mt, seed = 2))
    d <- koh_data(field, runs)
    stopifnot(!is.null(d$grid))
    sd_grid <- bayesbem:::koh_stan_data(d, koh_priors(), structure = "grid")
    sd_dense <- bayesbem:::koh_stan_data(d, koh_priors(), structure = "dense")
    g_grid <- grad_time(bayesbem:::stanmodels$koh, sd_grid, 20)
    N <- n * (mt + 1)
    # The dense gradient's Cholesky of the N x N Sigma_z costs O(N^3) time and
    # O(N^2) autodiff memory; past N_dense_max it is extrapolated as N^3 from
    # the largest size measured rather than run (about 2 min and 4 GB at N = 11,315).
    if (N <= N_dense_max) {
      g_dense <- grad_time(bayesbem:::stanmodels$koh, sd_dense, if (N > 1500) 1 else 5)
      dense_ref <- c(N = N, g = g_dense)
      dense_how <- "measured"
    } else {
      g_dense <- dense_ref[["g"]] * (N / dense_ref[["N"]])^3
      dense_how <- sprintf("extrapolated (N^3 from N = %d)", dense_ref[["N"]])
    }
    if (n <= fit_max_n) {
      wall <- system.time(fit <- suppressWarnings(
        calibrate(d, chains = 4, iter = 1000, seed = 3, cores = 2, refresh = 0)
      ))[["elapsed"]]
      s <- summary(fit)
      all_s <- rbind(s$parameters, s$hyperparameters)
      n_grad <- sum(unlist(lapply(bayesbem:::sampler_params(fit), `[`, , "n_leapfrog__"))) /
        (1 - fit$settings$warmup / fit$settings$iter)
      grads_ref[[as.character(mt)]] <- c(n = n, grads = n_grad)
      fit_note <- ""
    } else {
      # not run: the gradients the largest fitted size of this mt used, at
      # this size's time per gradient, two chains at a time
      ref <- grads_ref[[as.character(mt)]]
      n_grad <- ref[["grads"]]
      wall <- NA_real_
      all_s <- data.frame(rhat = NA_real_, ess_bulk = NA_real_)
      fit_note <- sprintf("not run (est. %.0f min with n = %d's %.0f gradients)",
                          n_grad * g_grid / 2 / 60, ref[["n"]], n_grad)
    }
    dense_estimate <- n_grad * g_dense / 2
    dense_wall <- if (dense_estimate < 1800) {
      system.time(suppressWarnings(
        calibrate(d, chains = 4, iter = 1000, seed = 3, cores = 2, refresh = 0,
                  structure = "dense")
      ))[["elapsed"]]
    } else {
      NA_real_
    }
    rows[[length(rows) + 1]] <- data.frame(
      n = n, mt = mt, N = n * (mt + 1), grad_grid_ms = 1000 * g_grid,
      grad_dense_ms = 1000 * g_dense, grad_dense = dense_how, fit_grid_s = wall, max_rhat = max(all_s$rhat),
      min_ess_bulk = min(all_s$ess_bulk), fit_grid_note = fit_note, fit_dense_s = dense_wall,
      dense_note = if (is.na(dense_wall)) sprintf("skipped (est. %.0f min)", dense_estimate / 60) else ""
    )
    print(rows[[length(rows)]], digits = 3, row.names = FALSE)
  }
}
cat("\nAll sizes (4 chains x 1000 iterations, 2 cores):\n")
print(do.call(rbind, rows), digits = 3, row.names = FALSE)
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\n", Sys.info()[["nodename"]],
            parallel::detectCores(), getRversion(), packageVersion("rstan"), Sys.Date()))
