# The modular KOH fit (Liu, Bayarri & Berger 2009, "Modularization in
# Bayesian analysis, with emphasis on analysis of computer models"): stage 1
# estimates the emulator's hyperparameters from the simulation runs alone
# by the mode of their posterior (inst/stan/koh.stan, likelihood
# "emulator"), stage 2 calibrates tf, the discrepancy and the noise with the
# emulator fixed there (likelihood "modular"), the "plug-in" emulator of Bayarri et al.
# (2007, "A framework for validation of computer models"). Cutting the
# feedback from the field data to the emulator removes the emulator modes
# that the field data favour at large n, and makes each stage-2 gradient one
# n x n Cholesky factor. A mode rather than draws: with few runs the
# posterior of the length scales has modes of equal mass that chains cross
# once in thousands of draws (bench/results/), so no fit that samples
# them passes R-hat, while the calibration agrees across them.

# Stage 1: the emulator at the posterior mode of its hyperparameters given
# the runs (highest_mode()), as calibrate() stores it in `fit$emulator`:
# `beta_eta`, `lambda_eta`, `b`, the mode's log density `lp` and the log
# densities each search reached (`searches`). When no search can start
# (the density fails at every start), `on_failure(messages)` is called, as
# for a chain that cannot start.
fit_emulator <- function(data, priors, seed, on_failure, starts = 16L) {
  instance <- stan_instance(stanmodels$koh, emulator_stan_data(data, priors))
  mode <- highest_mode(instance, random_starts(instance, starts, seed))
  if (!is.finite(mode$lp)) {
    on_failure(sprintf("Stage 1: the emulator's log density failed at all %d starting points.",
                       starts))
  }
  values <- rstan::constrain_pars(instance, mode$u)
  list(beta_eta = as.numeric(values$beta_eta), lambda_eta = as.numeric(values$lambda_eta),
       b = as.numeric(values$b %||% numeric()), lp = mode$lp, searches = mode$searches)
}

# An instance of `model` on `stan_data` whose log density and gradient
# rstan evaluates (rstan says that 0 chains sample nothing).
stan_instance <- function(model, stan_data) {
  utils::capture.output(suppressMessages(
    instance <- rstan::sampling(model, data = stan_data, chains = 0L)
  ))
  instance
}

# The highest mode of a model instance's log density on Stan's unconstrained
# scale, Jacobian included (where the Beta priors on rho keep every mode
# inside (0, 1); on the constrained scale the Beta(1, 0.3) density is
# unbounded at rho = 1), by BFGS from each column of `inits`. Returns `u`,
# its log density `lp` (-Inf when no search could start) and the log
# density each search reached (`searches`).
highest_mode <- function(instance, inits) {
  climbs <- lapply(seq_len(ncol(inits)), function(k) climb_log_prob(instance, inits[, k]))
  lp <- vapply(climbs, `[[`, numeric(1), "lp")
  best <- which.max(lp)
  list(u = climbs[[best]]$u, lp = lp[best], searches = lp)
}

# `starts` points on a model instance's unconstrained scale drawn as Stan
# draws its inits, U(-2, 2): a matrix, a column each.
random_starts <- function(instance, starts, seed) {
  d <- rstan::get_num_upars(instance)
  with_seed(seed, matrix(stats::runif(d * starts, -2, 2), d))
}

# The mode reached by BFGS from `u` and its log density (-Inf when the
# density cannot be evaluated at `u`). Where the density fails (a Cholesky
# factor near singular) it is taken as -1e300, so the line search backs
# off; a gradient that fails is taken as zero, which ends the search there.
climb_log_prob <- function(instance, u) {
  log_density <- function(x) {
    v <- tryCatch(rstan::log_prob(instance, x), error = function(e) -Inf)
    if (is.finite(v)) v else -1e300
  }
  gradient <- function(x) {
    g <- tryCatch(rstan::grad_log_prob(instance, x), error = function(e) NA)
    if (all(is.finite(g))) as.numeric(g) else numeric(length(x))
  }
  if (log_density(u) <= -1e300) {
    return(list(u = u, lp = -Inf))
  }
  res <- stats::optim(u, function(x) -log_density(x), function(x) -gradient(x), method = "BFGS",
                      control = list(maxit = 1000L, reltol = 1e-12))
  list(u = res$par, lp = -res$value)
}

# How many of stage 1's searches reached its mode (within 0.01 of its log
# density): few means other starts could find a higher one.
searches_at_mode <- function(searches) sum(searches >= max(searches) - 0.01)

# The same, for the summary.
emulator_searches_label <- function(searches) {
  sprintf("%d of %d searches reached it", searches_at_mode(searches), length(searches))
}
