# Benchmark (issue 14, coverage at 365 days): would a principal-component
# (basis) emulator (Higdon, Gattiker, Williams & Rightley 2008, JASA 103,
# "Computer model calibration using high-dimensional output") make the
# calibration honest where the package's separable emulator is not? A
# prototype outside the package, on the problems of bench-reliability.R
# (bayesbem:::synthetic_problem(): the embedded model, the truth within the
# ranges, noise 2 % of the mean output, correct simulator).
#
# Stage 1 (R): the runs' outputs at the field rows, scaled as koh_data()
# scales y, centred by their mean over the runs and decomposed by SVD,
# E - mu = K W' + residual, keeping the fewest components that hold
# `BENCH_VAR` of the variance (default 0.999); the truncated components
# become a white variance s2r per row. Each column of W (unit variance over
# the runs) gets its own Gaussian process over the scaled parameters
# (linear mean, squared-exponential kernel, variance and nugget), fitted by
# maximum marginal likelihood (ML-II, the mean profiled out).
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

# Per-column squared differences between the rows of a and b, and the
# squared-exponential correlation with weights beta.
sq_diffs <- function(a, b) lapply(seq_len(ncol(a)), function(k) outer(a[, k], b[, k], "-")^2)
sq_exp <- function(d, beta) exp(-Reduce(`+`, Map(`*`, d, beta)))

# One component's Gaussian process by ML-II: w ~ N(H b, s2 (C + nug I)),
# H = [1, t], b profiled out by generalised least squares; three starts.
fit_component <- function(tc, w) {
  d <- sq_diffs(tc, tc)
  h <- cbind(1, tc)
  q <- ncol(tc)
  cov_of <- function(th) {
    exp(th[q + 1]) * (sq_exp(d, exp(th[1:q])) + diag(exp(th[q + 2]) + 1e-8, nrow(tc)))
  }
  neg_log_lik <- function(th) {
    r <- tryCatch(chol(cov_of(th)), error = function(e) NULL)
    if (is.null(r)) return(1e10)
    wh <- backsolve(r, h, transpose = TRUE)
    ww <- backsolve(r, w, transpose = TRUE)
    res <- ww - wh %*% qr.solve(wh, ww)
    0.5 * sum(res^2) + sum(log(diag(r)))
  }
  fits <- lapply(c(-1, 1, 3), function(start) {
    stats::optim(c(rep(start, q), 0, -6), neg_log_lik, method = "L-BFGS-B",
                 lower = c(rep(-5, q), -6, -14), upper = c(rep(8, q), 6, 0))
  })
  th <- fits[[which.min(vapply(fits, `[[`, numeric(1), "value"))]]$par
  ki <- solve(cov_of(th))
  b <- solve(t(h) %*% ki %*% h, t(h) %*% ki %*% w)
  list(beta = exp(th[1:q]), s2 = exp(th[q + 1]), nug = exp(th[q + 2]), ki = ki, b = drop(b),
       alpha = drop(ki %*% (w - h %*% b)))
}

# The basis emulator of problem k.
basis_emulator <- function(n, mt, k) {
  problem <- ns$synthetic_problem(n, mt, k)
  data <- koh_data(problem$field, problem$runs)
  sc <- data$scaling
  names_t <- data$names$t
  runs <- problem$runs
  run_key <- ns$value_keys(runs[names_t])
  settings <- unique(runs[names_t])
  rows <- match(ns$value_keys(problem$field[data$names$x]), ns$value_keys(runs[data$names$x]))
  period_key <- ns$value_keys(runs[data$names$x])
  field_key <- period_key[rows]
  e <- vapply(ns$value_keys(settings), function(s) {
    one <- runs[run_key == s, ]
    (one$eta[match(field_key, ns$value_keys(one[data$names$x]))] - sc$y_center) / sc$y_scale
  }, numeric(nrow(problem$field)))
  tc <- ns$scale_t(as.matrix(settings), sc)
  mu <- rowMeans(e)
  sv <- svd(e - mu)
  pc <- which(cumsum(sv$d^2) / sum(sv$d^2) >= var_kept)[1]
  basis <- sv$u[, seq_len(pc), drop = FALSE] %*% diag(sv$d[seq_len(pc)] / sqrt(ncol(e)), pc)
  w <- sqrt(ncol(e)) * sv$v[, seq_len(pc), drop = FALSE]
  truncated <- e - mu - basis %*% t(w)
  list(problem = problem, data = data, tc = tc, mu = mu, basis = basis, pc = pc,
       s2r = mean(truncated^2),
       components = lapply(seq_len(pc), function(j) fit_component(tc, w[, j])),
       noise_sd = 0.02 * mean(attr(problem$field, "simulated")) / sc$y_scale)
}

# The emulator's mean and component variances at scaled parameters t.
emulate <- function(em, t) {
  wv <- vapply(em$components, function(gp) {
    k <- gp$s2 * drop(sq_exp(sq_diffs(matrix(t, 1), em$tc), gp$beta))
    c(sum(c(1, t) * gp$b) + sum(k * gp$alpha),
      max(gp$s2 * (1 + gp$nug) - drop(k %*% gp$ki %*% k), 0))
  }, numeric(2))
  list(mean = drop(em$mu + em$basis %*% wv[1, ]), var = wv[2, ])
}

honesty <- function(em, k) {
  names_t <- em$data$names$t
  ranges <- em$problem$simulator$parameters
  ranges <- ranges[ranges$parameter %in% names_t, ]
  points <- as.matrix(design_lhs(ranges, n = 40, seed = 99 + k)[names_t])
  z <- t(apply(points, 1, function(tv) {
    t0 <- drop(ns$scale_t(matrix(tv, 1, dimnames = list(NULL, names_t)), em$data$scaling))
    sim <- attr(ns$simulate_field(em$problem$simulator, as.list(tv)), "simulated")
    at <- emulate(em, t0)
    e <- (sim - em$data$scaling$y_center) / em$data$scaling$y_scale - at$mean
    j <- vapply(seq_along(t0), function(i) {
      up <- t0
      down <- t0
      up[i] <- min(up[i] + 0.01, 1)
      down[i] <- max(down[i] - 0.01, 0)
      (emulate(em, up)$mean - emulate(em, down)$mean) / (up[i] - down[i])
    }, numeric(length(e)))
    s <- em$basis %*% (at$var * t(em$basis))
    diag(s) <- diag(s) + em$s2r + em$noise_sd^2
    sj <- solve(s, j)
    a <- solve(crossprod(j, sj))
    drop(a %*% crossprod(sj, e)) / sqrt(diag(a))
  }))
  list(over = colMeans(abs(z) > 1.645), median = apply(abs(z), 2, stats::median))
}

stage2 <- function(em, k, model) {
  gps <- em$components
  mt <- nrow(em$tc)
  stan_data <- list(
    n = length(em$mu), pc = em$pc, q = ncol(em$tc), mt = mt,
    r0 = (em$problem$field$y - em$data$scaling$y_center) / em$data$scaling$y_scale - em$mu,
    K = em$basis, s2r = em$s2r, tc = em$tc,
    alpha = matrix(vapply(gps, `[[`, numeric(mt), "alpha"), mt),
    bcoef = matrix(vapply(gps, `[[`, numeric(ncol(em$tc) + 1), "b"), ncol = em$pc),
    beta = matrix(vapply(gps, `[[`, numeric(ncol(em$tc)), "beta"), ncol = em$pc),
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
    em <- basis_emulator(as.integer(s[1]), as.integer(s[2]), kk)
    h <- honesty(em, kk)
    row <- data.frame(n = s[1], mt = s[2], problem = kk, components = em$pc,
                      truncated_sd_over_noise = round(sqrt(em$s2r) / em$noise_sd, 2),
                      over_1.645 = paste(sprintf("%.2f", h$over), collapse = " "),
                      median_abs_z = paste(sprintf("%.2f", h$median), collapse = " "))
    if (run_fits) row <- cbind(row, stage2(em, kk, model))
    print(row, row.names = FALSE)
  }
}
