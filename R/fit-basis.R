# The basis emulator of a modular fit (Higdon, Gattiker, Williams &
# Rightley 2008, "Computer model calibration using high-dimensional
# output", JASA 103): the runs' outputs at the n field rows, centred by their
# mean over the runs, are decomposed E - mu = B W' + R (singular value
# decomposition), B the first components (n x pc), W their weights (runs x
# pc, unit variance over the runs) and R the truncated components, taken as
# white error of variance s2r per row. Each column of W is emulated over
# the calibration parameters by its own Gaussian process, fitted here by
# maximum marginal likelihood; stage 2 (inst/stan/koh_basis.stan)
# calibrates with them fixed. Why: the separable emulator gives its error
# the outputs' shape across periods, one correlation in the parameters for
# every component, which understates the error that moves the calibration
# at a year of daily data; components with their own length scales state
# it (bench/results/emulator-error.md and basis-emulator.md).

# Stage 1 of the basis emulator on a grid design: `mu`, the basis `B`,
# `s2r`, the runs `tc` (scaled), the runs' weights `w` and one
# fit_component() per component, keeping the fewest components that hold
# `variance` of the centred runs' variance.
basis_emulator <- function(data, variance = 0.999) {
  e <- field_runs(data)
  mu <- rowMeans(e)
  sv <- svd(e - mu)
  share <- cumsum(sv$d^2) / sum(sv$d^2)
  pc <- min(which(share >= variance - 1e-12), length(sv$d))
  keep <- seq_len(pc)
  runs <- ncol(e)
  basis <- sv$u[, keep, drop = FALSE] %*% diag(sv$d[keep] / sqrt(runs), pc)
  w <- sqrt(runs) * sv$v[, keep, drop = FALSE]
  truncated <- e - mu - basis %*% t(w)
  tc <- data$grid$design
  list(mu = mu, B = basis, s2r = mean(truncated^2), tc = tc, w = w, variance = variance,
       components = lapply(keep, function(j) fit_component(tc, w[, j])))
}

# One component's Gaussian process over the parameters tc (scaled to
# [0, 1]): w ~ N(H b, s2 (C + nug I)), H = (1, t), C[a, c] = exp(-sum_k
# beta[k] (t[a, k] - t[c, k])^2), by maximum marginal likelihood with b
# profiled out (generalised least squares), from three starts of the
# length scales. Returns beta, s2, nug, b, `ki` = (s2 (C + nug I))^-1 and
# `alpha` = ki (w - H b), what the predictions need.
fit_component <- function(tc, w) {
  q <- ncol(tc)
  d <- pair_geometry(tc, tc)$d
  h <- cbind(1, tc)
  unpack <- function(theta) {
    list(beta = exp(theta[seq_len(q)]), s2 = exp(theta[q + 1]), nug = exp(theta[q + 2]))
  }
  cov_of <- function(th) th$s2 * (exp(-weighted_sum(d, th$beta)) + diag(th$nug, nrow(tc)))
  objective <- function(theta) {
    r <- tryCatch(chol(cov_of(unpack(theta))), error = function(e) NULL)
    if (is.null(r)) {
      return(1e10)
    }
    component_gls(r, h, w)$deviance
  }
  searches <- lapply(c(-1, 1, 3), function(start) {
    stats::optim(c(rep(start, q), 0, -6), objective, method = "L-BFGS-B",
                 lower = c(rep(-5, q), -6, -14), upper = c(rep(8, q), 6, 0))
  })
  th <- unpack(searches[[which.min(vapply(searches, `[[`, numeric(1), "value"))]]$par)
  r <- chol(cov_of(th))
  ki <- chol2inv(r)
  b <- component_gls(r, h, w)$b
  c(th, list(b = b, ki = ki, alpha = drop(ki %*% (w - h %*% b))))
}

# w ~ N(H b, R'R) with b at its generalised-least-squares estimate (least
# squares on the whitened R'^-1 H, R'^-1 w): `b`, and `deviance`, minus the
# log marginal likelihood less constants (half the squared whitened
# residual plus log|R|).
component_gls <- function(r, h, w) {
  wh <- backsolve(r, h, transpose = TRUE)
  ww <- backsolve(r, w, transpose = TRUE)
  b <- qr.solve(wh, ww)
  list(b = drop(b), deviance = 0.5 * sum((ww - wh %*% b)^2) + sum(log(diag(r))))
}

# The components' means and variances at scaled parameters tf, as
# basis_components() in koh_functions.stan: mean h(tf)' b + k' alpha,
# variance s2 (1 + nug) - k' ki k (at least 0).
basis_weights <- function(basis, tf) {
  wv <- vapply(basis$components, component_moments, numeric(2), tc = basis$tc, tf = tf)
  list(mean = wv[1, ], var = wv[2, ])
}

# One component's (fit_component() on the runs `tc`) mean and variance at
# the scaled parameters tf.
component_moments <- function(gp, tc, tf) {
  k <- gp$s2 * exp(-tf_distance(tc, tf, gp$beta))
  c(sum(c(1, tf) * gp$b) + sum(k * gp$alpha),
    max(gp$s2 * (1 + gp$nug) - drop(crossprod(k, gp$ki %*% k)), 0))
}

# The basis emulator's eta at the field rows for scaled parameters tf:
# `mean` mu + B w(tf) and `var`, the components' variances v(tf).
basis_eta <- function(basis, tf) {
  wv <- basis_weights(basis, tf)
  list(mean = basis$mu + drop(basis$B %*% wv$mean), var = wv$var)
}

# The field outputs given the runs under the basis emulator, for one draw
# (runs_field() of a basis fit): mean mu + B w(tf) (the emulator's; the
# discrepancy terms h' gamma are the caller's, as for field_given_runs()),
# covariance B diag(v(tf)) B' + Sigma_delta + s2r I + diag(noise) / lambda_e
# (with AR(1) noise, the last two times its correlation: noise_cov()).
basis_field <- function(g, par) {
  basis <- g$basis
  eta <- basis_eta(basis, par$tf)
  cov <- basis$B %*% (eta$var * t(basis$B)) + delta_cov(g$ff, par) +
    noise_cov(g, par, basis$s2r)
  list(mean = eta$mean, cov = cov)
}
