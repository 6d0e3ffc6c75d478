# The modular KOH fit (Liu, Bayarri & Berger 2009, "Modularization in
# Bayesian analysis, with emphasis on analysis of computer models"): stage 1
# learns the emulator's hyperparameters from the simulation runs alone
# (inst/stan/koh_emulator.stan), stage 2 calibrates tf, the discrepancy and
# the noise with the emulator fixed at the stage-1 posterior medians
# (inst/stan/koh_modular.stan). Cutting the feedback from the field data to
# the emulator removes the emulator modes that the field data favour at
# large n, and makes each stage-2 gradient one n x n Cholesky factor.

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

# Samples stage 1 and returns its stanfit and the emulator estimate: the
# posterior medians of beta_eta, lambda_eta and b.
fit_emulator <- function(data, priors, sampler) {
  stan_data <- emulator_stan_data(data, priors)
  stanfit <- do.call(sample_chains, c(list(stanmodels$koh_emulator, stan_data,
                                           label = "Stage 1: emulator"), sampler))
  pars <- c("beta_eta", "lambda_eta", if (stan_data$n_b > 0L) "b")
  medians <- lapply(stats::setNames(nm = pars), function(par) {
    apply(as.matrix(stanfit, pars = par), 2, stats::median)
  })
  list(stanfit = stanfit, beta_eta = medians$beta_eta, lambda_eta = medians$lambda_eta,
       b = medians[["b"]] %||% numeric())
}

# The data of koh_modular.stan: the field data, the priors, and the fixed
# emulator's pieces (the runs at the field inputs less the emulator mean,
# the field block of Kx, the Cholesky factor of Kt).
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
  c(list(n = n, mt = grid$mt, p = p, q = data$q, y = data$y, xf = xf, tc = grid$design),
    koh_prior_data(data, priors),
    list(beta_eta_fixed = as.array(emulator$beta_eta), lambda_eta_fixed = emulator$lambda_eta,
         b_fixed = as.array(emulator$b), E_f = E - grid_mean(xf, grid$design, coef),
         Kx_ff = jittered_cor(pair_geometry(xf, xf), beta_x, priors$nugget),
         Lt = t(chol(kt))))
}
