# The modular KOH fit (Liu, Bayarri & Berger 2009, "Modularization in
# Bayesian analysis, with emphasis on analysis of computer models"): stage 1
# estimates the emulator's hyperparameters from the simulation runs alone
# by the mode of their posterior (inst/stan/koh_emulator.stan), stage 2
# calibrates tf, the discrepancy and the noise with the emulator fixed there
# (inst/stan/koh_modular.stan), the "plug-in" emulator of Bayarri et al.
# (2007, "A framework for validation of computer models"). Cutting the
# feedback from the field data to the emulator removes the emulator modes
# that the field data favour at large n, and makes each stage-2 gradient one
# n x n Cholesky factor. A mode rather than draws: with few runs the
# posterior of the length scales has modes of equal mass that chains cross
# once in thousands of draws (bench/RESULTS.md), so no fit that samples
# them passes R-hat, while the calibration agrees across them.

# Stage 1 on at most `max_inputs` of the grid inputs (evenly spaced over the
# field inputs, then the further ones): the length scales of x are learnt
# from a few dozen inputs as well as from hundreds, at a fraction of the cost.
emulator_rows <- function(grid, max_inputs = 60L) {
  if (grid$n_x <= max_inputs) {
    return(seq_len(grid$n_x))
  }
  unique(round(seq(1, grid$n_x, length.out = max_inputs)))
}

# The data of koh_emulator.stan: the grid program's, on emulator_rows() of the
# grid inputs (the field outputs are not used).
emulator_stan_data <- function(data, priors) {
  stan_data <- koh_stan_data(data, priors, structure = "grid")
  rows <- emulator_rows(data$grid)
  stan_data$n_x <- length(rows)
  stan_data$eta <- stan_data$eta[rows, , drop = FALSE]
  stan_data$x_grid <- stan_data$x_grid[rows, , drop = FALSE]
  stan_data
}

# Stage 1: the emulator at the posterior mode of its hyperparameters given
# the runs (emulator_mode()), as calibrate() stores it in `fit$emulator`:
# `beta_eta`, `lambda_eta`, `b`, the mode's log density `lp` and the log
# densities each search reached (`searches`). When no search can start
# (the density fails at every start), `on_failure(messages)` is called, as
# for a chain that cannot start.
fit_emulator <- function(data, priors, seed, on_failure, starts = 16L) {
  stan_data <- emulator_stan_data(data, priors)
  # rstan says that 0 chains sample nothing
  utils::capture.output(suppressMessages(
    instance <- rstan::sampling(stanmodels$koh_emulator, data = stan_data, chains = 0L)
  ))
  mode <- emulator_mode(instance, starts, seed)
  if (!is.finite(mode$lp)) {
    on_failure(sprintf("Stage 1: the emulator's log density failed at all %d starting points.",
                       starts))
  }
  values <- rstan::constrain_pars(instance, mode$u)
  list(beta_eta = as.numeric(values$beta_eta), lambda_eta = values$lambda_eta,
       b = as.numeric(values$b %||% numeric()), lp = mode$lp, searches = mode$searches)
}

# The highest mode of a model instance's log density on Stan's unconstrained
# scale, Jacobian included (where the Beta priors on rho keep every mode
# inside (0, 1); on the constrained scale the Beta(1, 0.3) density is
# unbounded at rho = 1), by BFGS from `starts` points drawn as Stan draws
# its inits, U(-2, 2). Returns `u`, its log density `lp` (-Inf when no
# search could start) and the log density each search reached (`searches`).
emulator_mode <- function(instance, starts, seed) {
  d <- rstan::get_num_upars(instance)
  inits <- with_seed(seed, matrix(stats::runif(d * starts, -2, 2), d))
  climbs <- lapply(seq_len(starts), function(k) climb_log_prob(instance, inits[, k]))
  lp <- vapply(climbs, `[[`, numeric(1), "lp")
  best <- which.max(lp)
  list(u = climbs[[best]]$u, lp = lp[best], searches = lp)
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

# The data every stage-2 program takes: the field data, the priors and the
# separable stage-1 emulator (which koh_basis.stan passes through for
# predictions).
stage2_stan_data <- function(data, priors, emulator) {
  c(list(n = data$n, mt = data$grid$mt, p = data$p, q = data$q, y = data$y,
         xf = data$grid$x[seq_len(data$n), , drop = FALSE], tc = data$grid$design,
         lapack = as.integer(use_lapack())),
    koh_prior_data(data, priors),
    list(beta_eta_fixed = as.array(emulator$beta_eta), lambda_eta_fixed = emulator$lambda_eta,
         b_fixed = as.array(emulator$b)))
}

# The data of koh_modular.stan: stage2_stan_data() and the fixed emulator's
# pieces (the runs at the field inputs less the emulator mean, the field
# block of Kx, the Cholesky factor of Kt).
modular_stan_data <- function(data, priors, emulator) {
  grid <- data$grid
  n <- data$n
  p <- data$p
  xf <- grid$x[seq_len(n), , drop = FALSE]
  coef <- drop(mean_selection(priors, p, data$q) %*% emulator$b)
  if (length(coef) == 0L) coef <- numeric(1 + p + data$q)
  beta_x <- emulator$beta_eta[seq_len(p)]
  beta_t <- emulator$beta_eta[-seq_len(p)]
  E <- grid_runs(data)[seq_len(n), , drop = FALSE]
  kt <- jittered_cor(pair_geometry(grid$design, grid$design), beta_t, priors$nugget)
  c(stage2_stan_data(data, priors, emulator),
    list(E_f = E - grid_mean(xf, grid$design, coef),
         Kx_ff = jittered_cor(pair_geometry(xf, xf), beta_x, priors$nugget),
         Lt = t(chol(kt))))
}
