# The discrepancy at a cost that does not grow with the rows: an additive
# Hilbert-space approximate Gaussian process (Solin & Sarkka 2020, Stat
# Comput 30; Riutort-Mayol, Burkner, Andersen, Solin & Vehtari 2023,
# "Practical Hilbert space approximate Bayesian Gaussian processes for
# probabilistic programming", Stat Comput 33). The discrepancy is a sum of
# one Gaussian process per observable input,
#   k(x, x') = (p lambda)^-1 sum_k exp(-b_k (x_k - x'_k)^2),
# b_k = additive_beta(beta_k) (length scales at most 2.5 input ranges),
# each on the interval [-L, L] about the centre of its scaled input (in
# [0, 1]) approximated by the Laplacian's first m eigenfunctions there,
#   exp(-beta d^2) ~ sum_j S(omega_j) phi_j(x) phi_j(x'),
# phi_j(x) = L^-1/2 sin(omega_j (x - 1/2 + L)), omega_j = pi j / (2 L), S
# the kernel's spectral density (hsgp_spectral()). The discrepancy is then
# Phi b, b ~ N(0, diag(S)), with Phi (n x m p) fixed: the likelihood needs
# only its Gram matrix with the runs' basis and the outputs
# (koh_basis.stan), computed once. Additive rather than the product
# kernel of the exact programs: a product over p inputs needs m^p
# functions (inst/notes/decisions/S9-discrepancy-at-scale.md).

# The basis functions of each input: `m` frequencies omega_j = pi j / (2
# L) on [-L, L], L = `boundary` / 2 (the inputs' half-range times
# `boundary`). m = 40, boundary = 10: every length scale from rho_delta =
# 0.02 to the floor's within 0.025 of the kernel (test-gp-hsgp.R).
hsgp_design <- function(m = 40L, boundary = 10) {
  half_width <- boundary / 2
  list(m = m, boundary = boundary, half_width = half_width,
       omega = pi * seq_len(m) / (2 * half_width))
}

# The basis functions at scaled inputs x (n x p): n x (m p), input 1's m
# functions first.
hsgp_phi <- function(x, design) {
  x <- as.matrix(x)
  L <- design$half_width
  do.call(cbind, lapply(seq_len(ncol(x)), function(k) {
    sin(outer(x[, k] - 0.5 + L, design$omega)) / sqrt(L)
  }))
}

# The variance of each basis function's coefficient: the spectral density
# of exp(-b_k d^2) / (p lambda) at its frequency (Riutort-Mayol et al.
# 2023, Eq 1, squared length scale 1 / (2 b_k)), b_k = additive_beta(beta_k),
#   S_k(omega) = (p lambda)^-1 sqrt(pi / b_k) exp(-omega^2 / (4 b_k)),
# as hsgp_log_spectral() in koh_basis.stan (its log). Without the floor on b_k, S would
# vanish at every frequency as the length scale grows (the approximation
# has no constant function), and the log density would change doubly
# exponentially in logit(rho) near 1.
hsgp_spectral <- function(design, beta, lambda) {
  p <- length(beta)
  unlist(lapply(additive_beta(beta), function(b) {
    exp(0.5 * log(pi / b) - log(p * lambda) - design$omega^2 / (4 * b))
  }))
}

# Z = [B, Phi(x), M, r, h] of one output's rows (basis, scaled inputs, the
# rows' month indicators `months` if any (shift_columns()), outputs less
# the runs' mean, discrepancy terms): the columns whose Gram matrices
# koh_basis.stan and the additive conditionals read.
hsgp_columns <- function(basis, x, r, h, design, months = NULL) {
  cbind(basis, hsgp_phi(x, design), months, r, h)
}

# The approximate discrepancy covariance between the rows of x1 and x2.
hsgp_cov <- function(x1, x2, design, beta, lambda) {
  s <- hsgp_spectral(design, beta, lambda)
  hsgp_phi(x1, design) %*% (s * t(hsgp_phi(x2, design)))
}
