# Machinery shared by the studies (study_priors(), study_parameters()): fits
# run through future with progress, and the tables every study reports.

# Runs calibrate() once per element of `jobs` (argument lists), through
# future.apply so that the plan decides where fits run; named like `jobs`.
run_fits <- function(jobs) {
  progress <- progressr::progressor(along = jobs)
  # the jobs carry their seeds; keep the caller's generator as it was
  old_seed <- saved_seed()
  on.exit(restore_seed(old_seed), add = TRUE)
  fits <- future.apply::future_lapply(jobs, function(job) {
    fit <- do.call(calibrate, job)
    progress()
    fit
  }, future.seed = TRUE, future.packages = "bayesbem")
  stats::setNames(fits, names(jobs))
}

# Posterior summary of each fit's calibration parameters in physical units,
# one row per (study setting, parameter); `scaled` is the median on the
# parameter's design range mapped to [0, 1].
study_posteriors <- function(fits, key) {
  rows <- lapply(names(fits), function(label) {
    fit <- fits[[label]]
    draws <- parameter_draws(fit)
    q <- column_quantiles(draws, c(0.05, 0.25, 0.5, 0.75, 0.95))
    data.frame(setting = label, parameter = colnames(draws), mean = colMeans(draws),
               sd = apply(draws, 2, stats::sd), q,
               scaled = drop(scale_t(rbind(q[, "q50"]), fit$data$scaling)), row.names = NULL)
  })
  out <- do.call(rbind, rows)
  names(out)[1] <- key
  out
}

# CVRMSE/NMBE of each fit on its training data and on the held-out
# `newdata` and `obs`, one row per (setting, set).
study_metrics <- function(fits, key, newdata, obs, ndraws) {
  rows <- lapply(names(fits), function(label) {
    data.frame(setting = label, held_out_metrics(fits[[label]], newdata, obs, ndraws))
  })
  out <- do.call(rbind, rows)
  names(out)[1] <- key
  out
}

# What both studies print: a header (a cli template evaluated in the
# caller), the posterior table keyed by `key`, and the metrics table.
print_study <- function(x, key, header, digits, .envir = parent.frame()) {
  cat_lines(header, "", "Posteriors of the calibration parameters (physical units):",
            .envir = .envir)
  print_rounded(x$posteriors[c(key, "parameter", "mean", "sd", "q5", "q50", "q95")], digits)
  cat_lines("", "CVRMSE and NMBE of the calibrated predictions (percent):")
  print_rounded(x$metrics, digits)
  invisible(x)
}
