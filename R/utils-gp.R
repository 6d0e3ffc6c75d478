# Gaussian-process algebra of the KOH model in R, for prediction and
# diagnosis. It mirrors inst/stan/include/koh_functions.stan: squared input
# differences are computed once per data set, and each posterior draw only
# weights and exponentiates them.

# Per-column squared differences between the rows of a and b.
sq_diffs <- function(a, b) {
  lapply(seq_len(ncol(a)), function(k) outer(a[, k], b[, k], "-")^2)
}

# sum_k beta[k] * d[[k]]
weighted_sum <- function(d, beta) {
  out <- beta[1] * d[[1]]
  for (k in seq_along(d)[-1]) out <- out + beta[k] * d[[k]]
  out
}

# The squared differences a fitted KOH model needs, for its data and,
# optionally, for new (scaled) observable inputs `x_new`.
gp_geometry <- function(data, x_new = NULL) {
  g <- list(n = data$n, m = data$m, p = data$p, tc = data$tc, z = c(data$y, data$eta),
            d_ff = sq_diffs(data$xf, data$xf), d_fc = sq_diffs(data$xf, data$xc),
            d_cc = sq_diffs(cbind(data$xc, data$tc), cbind(data$xc, data$tc)))
  if (!is.null(x_new)) {
    g$d_sf <- sq_diffs(x_new, data$xf)
    g$d_sc <- sq_diffs(x_new, data$xc)
    g$d_ss <- sq_diffs(x_new, x_new)
  }
  g
}

# Posterior draws of the model's parameters on the Stan scale, one list per draw.
draw_parameters <- function(fit, ndraws = NULL) {
  sf <- fit$stanfit
  get <- function(par) as.matrix(sf, pars = par)
  tf <- get("tf")
  beta_eta <- get("beta_eta")
  beta_delta <- get("beta_delta")
  lambda <- cbind(get("lambda_eta"), get("lambda_delta"), get("lambda_e"))
  idx <- draw_subset(nrow(tf), ndraws)
  lapply(idx, function(i) {
    list(tf = tf[i, ], beta_eta = beta_eta[i, ], beta_delta = beta_delta[i, ],
         lambda_eta = lambda[i, 1], lambda_delta = lambda[i, 2], lambda_e = lambda[i, 3],
         nugget = fit$priors$nugget)
  })
}

# Evenly spaced draws, so that results do not depend on the random seed.
draw_subset <- function(total, ndraws) {
  if (is.null(ndraws) || ndraws >= total) {
    return(seq_len(total))
  }
  check_count(ndraws)
  unique(round(seq(1, total, length.out = ndraws)))
}

# t part of the squared distances from tf to every design row.
tf_distance <- function(tc, tf, beta_t) {
  colSums(beta_t * (t(tc) - as.vector(tf))^2)
}

# The x and t parts of a draw's emulator correlations: the x weights and the
# t part of the squared distances from tf to every design row.
draw_geometry <- function(g, par) {
  p <- g$p
  list(bx = par$beta_eta[seq_len(p)],
       d_tf = tf_distance(g$tc, par$tf, par$beta_eta[-seq_len(p)]))
}

# Emulator covariance between points at tf (x differences `d_x` to the
# design rows) and the design rows.
cov_to_design <- function(d_x, dg, lambda_eta) {
  exp(-sweep(weighted_sum(d_x, dg$bx), 2, dg$d_tf, "+")) / lambda_eta
}

# Sigma_z of z = (y, eta) for one draw (method section 1).
koh_sigma_z <- function(g, par, dg = draw_geometry(g, par)) {
  s_ff <- exp(-weighted_sum(g$d_ff, dg$bx)) / par$lambda_eta +
    exp(-weighted_sum(g$d_ff, par$beta_delta)) / par$lambda_delta
  diag(s_ff) <- diag(s_ff) + 1 / par$lambda_e + par$nugget
  s_fc <- cov_to_design(g$d_fc, dg, par$lambda_eta)
  s_cc <- exp(-weighted_sum(g$d_cc, par$beta_eta)) / par$lambda_eta
  diag(s_cc) <- diag(s_cc) + par$nugget
  rbind(cbind(s_ff, s_fc), cbind(t(s_fc), s_cc))
}

# Joint conditional distribution of (eta(x_new, tf), delta(x_new)) given z,
# for one draw: mean S21 S11^-1 z and covariance S22 - S21 S11^-1 S12, with
# one Cholesky factor of S11 = Sigma_z.
koh_conditional <- function(g, par) {
  dg <- draw_geometry(g, par)
  n_new <- nrow(g$d_ss[[1]])
  c_eta <- cbind(exp(-weighted_sum(g$d_sf, dg$bx)) / par$lambda_eta,
                 cov_to_design(g$d_sc, dg, par$lambda_eta))
  c_delta <- cbind(exp(-weighted_sum(g$d_sf, par$beta_delta)) / par$lambda_delta,
                   matrix(0, n_new, g$m))
  s21 <- rbind(c_eta, c_delta)
  s22 <- matrix(0, 2 * n_new, 2 * n_new)
  s22[seq_len(n_new), seq_len(n_new)] <- exp(-weighted_sum(g$d_ss, dg$bx)) / par$lambda_eta
  s22[n_new + seq_len(n_new), n_new + seq_len(n_new)] <-
    exp(-weighted_sum(g$d_ss, par$beta_delta)) / par$lambda_delta
  r <- chol(koh_sigma_z(g, par, dg))
  v <- backsolve(r, t(s21), transpose = TRUE)
  w <- backsolve(r, g$z, transpose = TRUE)
  list(mean = drop(crossprod(v, w)), cov = s22 - crossprod(v))
}

# One draw from N(mean, cov) for a covariance that may be singular to
# rounding: eigenvalues below zero are rounding error and are set to zero.
rmvnorm_psd <- function(mean, cov) {
  e <- eigen(cov, symmetric = TRUE)
  mean + drop(e$vectors %*% (sqrt(pmax(e$values, 0)) * stats::rnorm(length(mean))))
}
