# Benchmark (issue 14, coverage at 365 days): would a principal-component
# (basis) emulator (Higdon, Gattiker, Williams & Rightley 2008, JASA 103,
# "Computer model calibration using high-dimensional output") make the
# calibration honest where the package's separable emulator is not? On the
# problems of bench-reliability.R (bayesbem:::synthetic_problem(): the
# embedded model, the truth within the ranges, noise 2 % of the mean output,
# correct simulator).
#
# Stage 1 is the package's (bayesbem:::basis_emulator(), R/fit-basis.R): the
# runs' outputs at the field rows, scaled as koh_data() scales y, centred by
# their mean over the runs and decomposed by SVD, E - mu = K W' + residual,
# keeping the fewest components that hold `BENCH_VAR` of the variance
# (default 0.999, the package's); the truncated components become a white
# variance s2r per row. Each column of W gets its own Gaussian process over
# the scaled parameters (linear mean, squared-exponential kernel, variance
# and nugget), fitted by maximum marginal likelihood.
#
# 1. Honesty, as bench-emulator-error.R measures the separable emulator: at
#    40 new parameter points (maximin LHS over the ranges) the emulator's
#    error e = simulator - emulator mean and the displacement of the
#    calibration it implies, Delta = (J' S^-1 J)^-1 J' S^-1 e, with
#    S = K diag(v) K' + (s2r + noise^2) I the basis emulator's stated
#    covariance plus the noise, standardised by its sd. Share of points with
#    |z| > 1.645 (10 % if S is honest) and median |z| (0.67 if honest).
# 2. With BENCH_FIT=1, stage 2 in Stan (bench/basis_stage2.stan: tf and the
#    noise, no discrepancy), 4 chains x 2000, adapt_delta 0.9, metric
#    BENCH_METRIC (default "dense_e"): coverage of the truth by the 90 %
#    intervals, (posterior mean - truth) / sd, max R-hat, min ESS (rstan's
#    n_eff), divergent transitions and wall time.
#
# Usage, from the package root, with bayesbem installed (rstan's
# stan_model() needs BH's headers; Debian's r-cran-bh has none: put first in
# R_LIBS a copy of BH whose include/boost links /usr/include/boost):
#   [BENCH_FIT=1] Rscript bench/bench-basis-emulator.R [n:mt:problems, comma-separated; default 365:30:1-6]
suppressPackageStartupMessages(library(bayesbem))
ns <- asNamespace("bayesbem")
options(width = 250)
args <- commandArgs(trailingOnly = TRUE)
spec <- if (length(args) > 0) args[1] else "365:30:1-6"
var_kept <- as.numeric(Sys.getenv("BENCH_VAR", "0.999"))
run_fits <- Sys.getenv("BENCH_FIT") == "1"
metric <- Sys.getenv("BENCH_METRIC", "dense_e")

# The basis emulator of problem k: the package's stage 1
# (bayesbem:::basis_emulator()) on the problem's data, and the noise sd on
# the scale of koh_data()'s y.
problem_emulator <- function(n, mt, k) {
  problem <- ns$synthetic_problem(n, mt, k)
  data <- koh_data(problem$field, problem$runs)
  list(problem = problem, data = data, basis = ns$basis_emulator(data, var_kept),
       noise_sd = 0.02 * mean(attr(problem$field, "simulated")) / data$scaling$y_scale)
}

honesty <- function(em, k) {
  names_t <- em$data$names$t
  ranges <- em$problem$simulator$parameters
  ranges <- ranges[ranges$parameter %in% names_t, ]
  points <- as.matrix(design_lhs(ranges, n = 40, seed = 99 + k)[names_t])
  z <- t(apply(points, 1, function(tv) {
    t0 <- drop(ns$scale_t(matrix(tv, 1, dimnames = list(NULL, names_t)), em$data$scaling))
    sim <- attr(ns$simulate_field(em$problem$simulator, as.list(tv)), "simulated")
    at <- ns$basis_eta(em$basis, t0)
    e <- (sim - em$data$scaling$y_center) / em$data$scaling$y_scale - at$mean
    j <- vapply(seq_along(t0), function(i) {
      up <- t0
      down <- t0
      up[i] <- min(up[i] + 0.01, 1)
      down[i] <- max(down[i] - 0.01, 0)
      (ns$basis_eta(em$basis, up)$mean - ns$basis_eta(em$basis, down)$mean) / (up[i] - down[i])
    }, numeric(length(e)))
    s <- em$basis$B %*% (at$var * t(em$basis$B))
    diag(s) <- diag(s) + em$basis$s2r + em$noise_sd^2
    sj <- solve(s, j)
    a <- solve(crossprod(j, sj))
    drop(a %*% crossprod(sj, e)) / sqrt(diag(a))
  }))
  list(over = colMeans(abs(z) > 1.645), median = apply(abs(z), 2, stats::median))
}

stage2 <- function(em, k, model) {
  basis <- em$basis
  gps <- basis$components
  mt <- nrow(basis$tc)
  q <- ncol(basis$tc)
  stan_data <- list(
    n = length(basis$mu), pc = length(gps), q = q, mt = mt,
    r0 = em$data$y - basis$mu,
    K = basis$B, s2r = basis$s2r, tc = basis$tc,
    alpha = matrix(vapply(gps, `[[`, numeric(mt), "alpha"), mt),
    bcoef = matrix(vapply(gps, `[[`, numeric(q + 1), "b"), ncol = length(gps)),
    beta = matrix(vapply(gps, `[[`, numeric(q), "beta"), ncol = length(gps)),
    s2 = vapply(gps, `[[`, numeric(1), "s2"), nug = vapply(gps, `[[`, numeric(1), "nug"),
    Ki = do.call(rbind, lapply(gps, `[[`, "ki")))
  start <- Sys.time()
  fit <- suppressWarnings(rstan::sampling(model, stan_data, chains = 4, iter = 2000, cores = 2,
                                          seed = 4000 + k, refresh = 0,
                                          control = list(adapt_delta = 0.9, metric = metric)))
  wall <- as.numeric(difftime(Sys.time(), start, units = "secs"))
  tf <- as.matrix(fit, pars = "tf")
  truth <- drop(ns$scale_t(matrix(unlist(em$problem$truth), 1,
                                  dimnames = list(NULL, em$data$names$t)), em$data$scaling))
  ends <- apply(tf, 2, stats::quantile, c(0.05, 0.95))
  s <- rstan::summary(fit, pars = "tf")$summary
  data.frame(covered = sprintf("%d/%d", sum(truth >= ends[1, ] & truth <= ends[2, ]), length(truth)),
             mean_minus_truth_sd = paste(sprintf("%.2f", (colMeans(tf) - truth) / apply(tf, 2, stats::sd)),
                                         collapse = " "),
             rhat = round(max(s[, "Rhat"]), 3), ess = round(min(s[, "n_eff"])),
             divergent = sum(rstan::get_divergent_iterations(fit)), wall_s = round(wall))
}

cat(sprintf("machine: %s, %d cores; R %s; date %s; variance kept %s; metric %s\nparameters (in this order): %s\n\n",
            Sys.info()[["nodename"]], parallel::detectCores(), getRversion(), Sys.Date(), var_kept,
            metric, "fan_total_efficiency equipment_power_density infiltration_per_exterior_area"))
model <- if (run_fits) rstan::stan_model(file.path("bench", "basis_stage2.stan"))
for (s in strsplit(strsplit(spec, ",")[[1]], ":")) {
  k <- as.integer(strsplit(s[3], "-")[[1]])
  for (kk in seq(k[1], k[length(k)])) {
    em <- problem_emulator(as.integer(s[1]), as.integer(s[2]), kk)
    h <- honesty(em, kk)
    row <- data.frame(n = s[1], mt = s[2], problem = kk, components = length(em$basis$components),
                      truncated_sd_over_noise = round(sqrt(em$basis$s2r) / em$noise_sd, 2),
                      over_1.645 = paste(sprintf("%.2f", h$over), collapse = " "),
                      median_abs_z = paste(sprintf("%.2f", h$median), collapse = " "))
    if (run_fits) row <- cbind(row, stage2(em, kk, model))
    print(row, row.names = FALSE)
  }
}
