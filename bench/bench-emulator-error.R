# Benchmark (issue 14, coverage): does the emulator's stated uncertainty
# cover the error that moves the calibration? For each synthetic problem of
# bench-reliability.R (bayesbem:::synthetic_problem(), noise 2 % of the mean
# output), the stage-1 emulator of a modular fit (the mode of its
# hyperparameters given the runs), then at 40 new parameter points (a
# maximin LHS over the three parameters' ranges) the emulator's error at
# the field rows, e = simulator - emulator mean given the runs, and the
# displacement of the calibration that e implies: Delta = (J' S^-1 J)^-1
# J' S^-1 e (J the emulator mean's sensitivity, as validate_emulator()),
# standardised by its own sd, sqrt(diag((J' S^-1 J)^-1)). Were the stated
# covariance S right, |z| > 1.645 would happen at 10 % of the points.
# S is, in turn:
#   stated: the emulator's covariance given the runs plus the noise (the
#           stage-2 likelihood without a discrepancy);
#   loo:    that plus the covariance of the runs' leave-one-run-out
#           errors at the field rows (each run predicted from the others);
#   oracle: that plus the covariance of the errors at the other 39 points.
# Reported per problem and S: the share of points with |z| > 1.645 and the
# median |z| for each parameter, and the error's RMSE over the noise sd.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-emulator-error.R [n:mt:problems, comma-separated; default 365:30:1-6]
suppressPackageStartupMessages(library(bayesbem))
ns <- asNamespace("bayesbem")
options(width = 200)
args <- commandArgs(trailingOnly = TRUE)
spec <- if (length(args) > 0) args[1] else "365:30:1-6"
priors <- koh_priors()

# The stage-1 emulator of problem k and what its errors are measured with.
problem_emulator <- function(n, mt, k) {
  problem <- ns$synthetic_problem(n, mt, k)
  data <- koh_data(problem$field, problem$runs)
  em <- ns$fit_emulator(data, priors, 4000 + k, stop)
  coef <- drop(ns$mean_selection(priors, data$p, data$q) %*% em$b)
  noise_sd <- 0.02 * mean(attr(problem$field, "simulated")) / data$scaling$y_scale
  # a draw with no discrepancy and the problem's noise
  par <- list(beta_eta = em$beta_eta, lambda_eta = em$lambda_eta, coef = coef,
              nugget = priors$nugget, beta_delta = rep(1, data$p), lambda_delta = Inf,
              lambda_e = 1 / noise_sd^2)
  list(problem = problem, data = data, g = ns$gp_geometry(data, structure = "grid"), par = par,
       noise_sd = noise_sd)
}

# Leave-one-run-out errors of the runs at the field rows (field rows by
# runs): for a GP interpolant, (E K^-1)_a / (K^-1)_aa (Dubrule 1983).
loo_errors <- function(em) {
  g <- ns$residual_geometry(em$g, c(em$par, list(tf = rep(0.5, em$data$q))))
  kt <- ns$jittered_cor(g$tt, em$par$beta_eta[-seq_len(em$data$p)], priors$nugget)
  inv <- solve(kt)
  sweep(g$E[seq_len(em$data$n), , drop = FALSE] %*% inv, 2, diag(inv), "/")
}

# Error, sensitivity and stated covariance at physical parameter values tv.
at_point <- function(em, tv) {
  names_t <- em$data$names$t
  par <- em$par
  par$tf <- drop(ns$scale_t(matrix(tv, 1, dimnames = list(NULL, names_t)), em$data$scaling))
  fm <- ns$runs_field(em$g, par)
  sim <- attr(ns$simulate_field(em$problem$simulator, as.list(stats::setNames(tv, names_t))),
              "simulated")
  s <- (sim - em$data$scaling$y_center) / em$data$scaling$y_scale
  list(e = s - fm$mean,
       J = ns$runs_sensitivity(em$g, par), S = fm$cov)
}

standardised_shift <- function(pt, extra) {
  sj <- solve(pt$S + extra, pt$J)
  a <- solve(crossprod(pt$J, sj))
  drop(a %*% crossprod(sj, pt$e)) / sqrt(diag(a))
}

one_problem <- function(n, mt, k) {
  em <- problem_emulator(n, mt, k)
  names_t <- em$data$names$t
  ranges <- em$problem$simulator$parameters
  ranges <- ranges[ranges$parameter %in% names_t, ]
  points <- as.matrix(design_lhs(ranges, n = 40, seed = 99 + k)[names_t])
  pts <- lapply(seq_len(nrow(points)), function(i) at_point(em, points[i, ]))
  errors <- sapply(pts, `[[`, "e")
  loo <- loo_errors(em)
  v_loo <- tcrossprod(loo) / ncol(loo)
  z <- list(
    stated = t(sapply(pts, standardised_shift, extra = 0)),
    loo = t(sapply(pts, standardised_shift, extra = v_loo)),
    oracle = t(sapply(seq_along(pts), function(i) {
      standardised_shift(pts[[i]], tcrossprod(errors[, -i]) / (ncol(errors) - 1))
    }))
  )
  do.call(rbind, lapply(names(z), function(s) {
    data.frame(n = n, mt = mt, problem = k, covariance = s,
               over_1.645 = paste(sprintf("%.2f", colMeans(abs(z[[s]]) > 1.645)), collapse = " "),
               median_abs_z = paste(sprintf("%.2f", apply(abs(z[[s]]), 2, stats::median)),
                                    collapse = " "),
               rmse_over_noise = round(sqrt(mean(errors^2)) / em$noise_sd, 2))
  }))
}

cat(sprintf("machine: %s, %d cores; R %s; date %s\nparameters (in this order): %s\n\n",
            Sys.info()[["nodename"]], parallel::detectCores(), getRversion(), Sys.Date(),
            "fan_total_efficiency equipment_power_density infiltration_per_exterior_area"))
for (s in strsplit(strsplit(spec, ",")[[1]], ":")) {
  k <- as.integer(strsplit(s[3], "-")[[1]])
  for (kk in seq(k[1], k[length(k)])) {
    print(one_problem(as.integer(s[1]), as.integer(s[2]), kk), row.names = FALSE)
  }
}
