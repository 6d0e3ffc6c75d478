# The Gaussian-process kernels in R, mirroring
# inst/stan/include/koh_functions.stan: squared input differences computed
# once per pair of row sets, weighted and exponentiated per draw; the
# emulator's mean.

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

# Equal-row indicators of a and b, the rows where the kernel jitter applies.
eq_rows <- function(a, b) {
  outer(row_keys(a), row_keys(b), "==") + 0
}

# Squared differences and equal-row indicators of the rows of a and b.
pair_geometry <- function(a, b) {
  list(d = sq_diffs(a, b), eq = eq_rows(a, b))
}

# t part of the squared distances from tf to every design row.
tf_distance <- function(tc, tf, beta_t) {
  colSums(beta_t * (t(tc) - as.vector(tf))^2)
}

# One factor of the emulator kernel with its jitter (koh_functions.stan's
# jittered_cor()): exp(-sum_k beta[k] d2_k) + nugget where rows are equal.
jittered_cor <- function(pair, beta, nugget) {
  exp(-weighted_sum(pair$d, beta)) + nugget * pair$eq
}

# Squared-exponential covariance of the discrepancy: a product over the
# inputs, or with `par$additive` their mean (gp-hsgp.R's kernel),
#   (p lambda)^-1 sum_k exp(-additive_beta(beta_k) d_k^2).
delta_cov <- function(pair, par) {
  if (isTRUE(par$additive)) {
    terms <- Map(function(d, b) exp(-b * d), pair$d, additive_beta(par$beta_delta))
    return(Reduce(`+`, terms) / (length(terms) * par$lambda_delta))
  }
  exp(-weighted_sum(pair$d, par$beta_delta)) / par$lambda_delta
}

# The additive kernel's inverse squared length scales: sqrt(beta^2 +
# 0.08^2), so that no length scale exceeds that of rho_delta = 0.98 (2.5
# input ranges, a kernel flat within 8 % over the inputs), the longest its
# Hilbert-space approximation holds (R/gp-hsgp.R); as koh_basis.stan's
# hsgp_spectral().
additive_beta <- function(beta, floor = 0.08) sqrt(beta^2 + floor^2)

# The emulator mean h(x, t)' b at rows x (scaled), all at the parameters t
# (one row) or each at its own (a matrix): koh_functions.stan's
# emulator_mean().
emulator_mean <- function(x, t, coef) {
  tc <- if (is.matrix(t)) t else matrix(t, nrow(x), length(t), byrow = TRUE)
  drop(coef[1] + x %*% coef[1 + seq_len(ncol(x))] + tc %*% coef[-seq_len(1 + ncol(x))])
}

# The emulator mean on a grid, element (i, a) at grid input i and run a
# (koh_functions.stan's grid_mean()).
grid_mean <- function(x_grid, tc, coef) {
  p <- ncol(x_grid)
  outer(coef[1] + drop(x_grid %*% coef[1 + seq_len(p)]), drop(tc %*% coef[-seq_len(1 + p)]), "+")
}
