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

# Starting values given as a list per chain (rstan::sampling()'s `init`), as
# the stage-2 programs take them: lambda_delta and lambda_e are vectors, one
# element per output, and a basis fit samples tf as tf_u (basis_inits()).
stage2_inits <- function(init, emulator) {
  if (emulator == "basis") init <- basis_inits(init)
  if (!is.list(init)) {
    return(init)
  }
  lapply(init, function(chain) {
    for (par in intersect(c("lambda_delta", "lambda_e"), names(chain))) {
      chain[[par]] <- as.array(chain[[par]])
    }
    chain
  })
}

# The data every stage-2 program takes, for one output or several (`data` a
# bayesbem_data or bayesbem_outputs object, `emulator` its stage-1 emulator
# or their list): the field data stacked by output (each on its own
# scaling), the runs' design they share, the priors, the discrepancy terms
# of each output in its own columns (zero in the others' rows), and the
# separable stage-1 emulators, one column each (koh_basis.stan passes them
# through for predictions).
stage2_stan_data <- function(data, priors, emulator) {
  outputs <- output_data(data)
  emulators <- output_emulators(data, emulator)
  first <- outputs[[1]]
  prior <- koh_prior_data(first, priors)
  prior$h <- block_diagonal(lapply(outputs, discrepancy_design))
  prior$n_h <- ncol(prior$h)
  c(list(n = sum(vapply(outputs, `[[`, integer(1), "n")), mt = first$grid$mt, p = first$p,
         q = first$q, y = unlist(lapply(outputs, `[[`, "y")),
         xf = do.call(rbind, lapply(outputs, function(d) d$grid$x[seq_len(d$n), , drop = FALSE])),
         tc = first$grid$design, K = length(outputs),
         output = as.array(rep(seq_along(outputs), vapply(outputs, `[[`, integer(1), "n"))),
         lapack = as.integer(use_lapack())),
    prior,
    list(beta_eta_fixed = emulator_columns(emulators, "beta_eta"),
         lambda_eta_fixed = as.array(vapply(emulators, `[[`, numeric(1), "lambda_eta")),
         b_fixed = emulator_columns(emulators, "b")))
}

# The one-output data sets of a data set, and their stage-1 emulators in the
# same order.
output_data <- function(data) {
  if (inherits(data, "bayesbem_outputs")) data$outputs else list(data)
}

output_emulators <- function(data, emulator) {
  if (inherits(data, "bayesbem_outputs")) emulator else list(emulator)
}

# One column per output of a stage-1 emulator's element (beta_eta, b).
emulator_columns <- function(emulators, name) {
  matrix(unlist(lapply(emulators, `[[`, name)), ncol = length(emulators))
}

# The matrices of `blocks` on the diagonal of one matrix, zero elsewhere.
block_diagonal <- function(blocks) {
  rows <- vapply(blocks, nrow, integer(1))
  cols <- vapply(blocks, ncol, integer(1))
  out <- matrix(0, sum(rows), sum(cols))
  for (k in seq_along(blocks)) {
    out[sum(rows[seq_len(k - 1L)]) + seq_len(rows[k]),
        sum(cols[seq_len(k - 1L)]) + seq_len(cols[k])] <- blocks[[k]]
  }
  out
}

# The data of koh_modular.stan: stage2_stan_data() and each output's fixed
# emulator's pieces, stacked by output: the runs at the field inputs less
# the emulator mean, the field block of Kx (its first columns), the
# Cholesky factor of Kt.
modular_stan_data <- function(data, priors, emulator) {
  pieces <- Map(modular_pieces, output_data(data), output_emulators(data, emulator),
                MoreArgs = list(priors = priors))
  kx <- lapply(pieces, `[[`, "Kx_ff")
  n_max <- max(vapply(kx, nrow, integer(1)))
  c(stage2_stan_data(data, priors, emulator),
    list(n_max = n_max, E_f = do.call(rbind, lapply(pieces, `[[`, "E_f")),
         Kx_ff = do.call(rbind, lapply(kx, function(k) cbind(k, matrix(0, nrow(k), n_max - ncol(k))))),
         Lt = do.call(rbind, lapply(pieces, `[[`, "Lt"))))
}

# One output's pieces of modular_stan_data().
modular_pieces <- function(data, emulator, priors) {
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
  list(E_f = E - grid_mean(xf, grid$design, coef),
       Kx_ff = jittered_cor(pair_geometry(xf, xf), beta_x, priors$nugget),
       Lt = t(chol(kt)))
}
