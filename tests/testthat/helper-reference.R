# An independent R transcription of the method's log density (method.md
# section 1): covariances element by element, the multivariate normal via
# chol(), and the priors with R's own density functions. Tests compare the
# Stan program against it.
reference_log_density <- function(sd, pars) {
  n <- sd$n
  m <- sd$m
  N <- n + m
  u <- rbind(cbind(sd$xf, matrix(pars$tf, n, sd$q, byrow = TRUE)),
             cbind(sd$xc, sd$tc))
  beta_eta <- -4 * log(pars$rho_eta)
  beta_delta <- -4 * log(pars$rho_delta)
  sigma <- matrix(0, N, N)
  for (i in seq_len(N)) {
    for (j in seq_len(N)) {
      sigma[i, j] <- exp(-sum(beta_eta * (u[i, ] - u[j, ])^2)) / pars$lambda_eta
    }
  }
  diag(sigma) <- diag(sigma) + sd$nugget
  for (i in seq_len(n)) {
    for (j in seq_len(n)) {
      sigma[i, j] <- sigma[i, j] +
        exp(-sum(beta_delta * (sd$xf[i, ] - sd$xf[j, ])^2)) / pars$lambda_delta +
        (i == j) / pars$lambda_e
    }
  }
  z <- c(sd$y, sd$eta)
  r <- chol(sigma)
  ll <- -0.5 * N * log(2 * pi) - sum(log(diag(r))) - 0.5 * sum(backsolve(r, z, transpose = TRUE)^2)
  lp_tf <- 0
  for (k in seq_len(sd$q)) {
    if (sd$tf_is_normal[k] == 1) {
      lp_tf <- lp_tf + stats::dnorm(pars$tf[k], sd$tf_mu[k], sd$tf_sd[k], log = TRUE) -
        log(stats::pnorm(1, sd$tf_mu[k], sd$tf_sd[k]) - stats::pnorm(0, sd$tf_mu[k], sd$tf_sd[k]))
    }
  }
  ll + lp_tf +
    sum(stats::dbeta(pars$rho_eta, sd$rho_eta_a, sd$rho_eta_b, log = TRUE)) +
    sum(stats::dbeta(pars$rho_delta, sd$rho_delta_a, sd$rho_delta_b, log = TRUE)) +
    stats::dgamma(pars$lambda_eta, sd$lambda_eta_shape, sd$lambda_eta_rate, log = TRUE) +
    stats::dgamma(pars$lambda_delta, sd$lambda_delta_shape, sd$lambda_delta_rate, log = TRUE) +
    stats::dgamma(pars$lambda_e, sd$lambda_e_shape, sd$lambda_e_rate, log = TRUE)
}

random_koh_pars <- function(sd) {
  list(tf = as.array(stats::runif(sd$q)),
       rho_eta = as.array(stats::runif(sd$p + sd$q, 0.3, 0.99)),
       rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
       lambda_eta = stats::rgamma(1, 10, 10),
       lambda_delta = stats::rgamma(1, 10, 0.3),
       lambda_e = stats::rgamma(1, 10, 0.03))
}

# The compiled KOH model with data `sd`, without sampling, for log_prob().
koh_model_for <- function(sd) {
  utils::capture.output(model <- rstan::sampling(bayesbem:::stanmodels$koh, data = sd, chains = 0))
  model
}

# Stan's log density (priors included, no Jacobian) at constrained `pars`.
stan_log_density <- function(model, pars) {
  rstan::log_prob(model, rstan::unconstrain_pars(model, pars), adjust_transform = FALSE)
}
