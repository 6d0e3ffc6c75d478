# Gaussian-process conditionals of the KOH model in R, for prediction and
# diagnosis, on the kernels of R/gp-kernels.R and the noise of
# R/gp-noise.R: for one draw of the parameters, the joint law of (eta,
# delta) at new inputs given the data, the field given the runs, and
# leave-one-out densities. What reads a fit (its draws, its basis
# emulator) is in R/predict-draws.R.

# The geometry a fitted KOH model needs for its data and, optionally, for new
# (scaled) observable inputs `x_new` at tf: pairs "ff" (field rows), "sf"
# and "ss" (new rows), and, for the dense structure, "fc", "sc", "cc" (x of
# simulation rows) and "tt" (t of simulation rows); for the grid structure,
# "xx" and "sx" (grid inputs, field inputs first), "tt" over the runs and the
# output matrix `E` (grid input by run). `basis`: a fit's basis emulator
# (basis_emulator()), which runs_field() then reads. `noise`: the field
# rows' noise weights (noise_weights()); `segments`: their AR(1) segments
# (data_segments()).
gp_geometry <- function(data, x_new = NULL, structure = "dense", basis = NULL) {
  g <- list(structure = structure, n = data$n, m = data$m, p = data$p, y = data$y,
            h = discrepancy_design(data), ff = pair_geometry(data$xf, data$xf),
            xf = data$xf, x_new = x_new, basis = basis, noise = noise_weights(data),
            segments = data_segments(data))
  if (is_grid(g)) {
    grid <- data$grid
    g$tc <- grid$design
    g$E <- grid_runs(data)
    g$field <- field_rows(grid)
    g$x_grid <- grid$x
    g$tt <- pair_geometry(g$tc, g$tc)
    g$xx <- pair_geometry(grid$x, grid$x)
    if (!is.null(x_new)) g$sx <- pair_geometry(x_new, grid$x)
  } else {
    g$tc <- data$tc
    g$xc <- data$xc
    g$eta <- data$eta
    g$fc <- pair_geometry(data$xf, data$xc)
    g$cc <- pair_geometry(data$xc, data$xc)
    g$tt <- pair_geometry(data$tc, data$tc)
  }
  if (!is.null(x_new)) {
    g$sf <- pair_geometry(x_new, data$xf)
    g$ss <- pair_geometry(x_new, x_new)
    if (!is_grid(g)) g$sc <- pair_geometry(x_new, data$xc)
  }
  g
}

# A draw's x weights, t weights and correlations k_t(tf, t_a) to the design.
draw_geometry <- function(g, par) {
  x <- seq_len(g$p)
  bt <- par$beta_eta[-x]
  list(bx = par$beta_eta[x], bt = bt, k0 = exp(-tf_distance(g$tc, par$tf, bt)))
}

# Emulator covariance of rows at tf (pair geometry `pair` to the field
# rows, or to the simulation rows with `to_design = TRUE`).
eta_cov <- function(pair, dg, par, to_design = FALSE) {
  kx <- jittered_cor(pair, dg$bx, par$nugget)
  t_factor <- if (to_design) rep(dg$k0, each = nrow(kx)) else 1 + par$nugget
  kx * t_factor / par$lambda_eta
}

# Sigma_z of z = (y, eta) for one draw of a dense design (method section 1,
# with the jitter of koh_cov()).
koh_sigma_z <- function(g, par, dg = draw_geometry(g, par)) {
  s_ff <- eta_cov(g$ff, dg, par) + delta_cov(g$ff, par)
  s_ff <- s_ff + noise_cov(g, par)
  s_fc <- eta_cov(g$fc, dg, par, to_design = TRUE)
  s_cc <- jittered_cor(g$cc, dg$bx, par$nugget) * jittered_cor(g$tt, dg$bt, par$nugget) /
    par$lambda_eta
  rbind(cbind(s_ff, s_fc), cbind(t(s_fc), s_cc))
}

# The field outputs less the draw's parametric discrepancy terms h' gamma,
# which is what the Gaussian processes model.
field_y <- function(g, par) {
  if (ncol(g$h) == 0L) g$y else g$y - drop(g$h %*% par$gamma)
}

# The geometry with the draw's emulator mean taken off the data (field
# outputs at tf, simulation outputs at their runs), which is what the
# Gaussian processes model; `mean_new`, the mean at the new rows, is added
# back to the emulator's conditional mean there.
residual_geometry <- function(g, par) {
  g$mean_new <- 0
  if (all(par$coef == 0)) {
    return(g)
  }
  g$y <- g$y - emulator_mean(g$xf, par$tf, par$coef)
  if (is_grid(g)) {
    g$E <- g$E - grid_mean(g$x_grid, g$tc, par$coef)
  } else {
    g$eta <- g$eta - emulator_mean(g$xc, g$tc, par$coef)
  }
  if (!is.null(g$x_new)) g$mean_new <- emulator_mean(g$x_new, par$tf, par$coef)
  g
}

# Joint conditional distribution of (eta(x_new, tf), delta(x_new)) given the
# data, for one draw: mean and covariance; delta is the Gaussian-process
# part of the discrepancy, eta includes the emulator mean.
koh_conditional <- function(g, par) {
  g <- residual_geometry(g, par)
  cond <- if (is_grid(g)) koh_conditional_grid(g, par) else koh_conditional_dense(g, par)
  eta_rows <- seq_len(nrow(g$ss$eq))
  cond$mean[eta_rows] <- cond$mean[eta_rows] + g$mean_new
  cond
}

# Any design: mean S21 S11^-1 z and covariance S22 - S21 S11^-1 S12, with one
# Cholesky factor of S11 = Sigma_z.
koh_conditional_dense <- function(g, par) {
  dg <- draw_geometry(g, par)
  n_new <- nrow(g$ss$eq)
  s21 <- rbind(cbind(eta_cov(g$sf, dg, par), eta_cov(g$sc, dg, par, to_design = TRUE)),
               cbind(delta_cov(g$sf, par), matrix(0, n_new, g$m)))
  r <- chol(koh_sigma_z(g, par, dg))
  v <- backsolve(r, t(s21), transpose = TRUE)
  w <- backsolve(r, c(field_y(g, par), g$eta), transpose = TRUE)
  list(mean = drop(crossprod(v, w)), cov = new_rows_cov(g, dg, par) - crossprod(v))
}

# Prior covariance of (eta, delta) at the new rows: block diagonal.
new_rows_cov <- function(g, dg, par) {
  n_new <- nrow(g$ss$eq)
  zero <- matrix(0, n_new, n_new)
  rbind(cbind(eta_cov(g$ss, dg, par), zero), cbind(zero, delta_cov(g$ss, par)))
}

# The field outputs given the simulation runs, for one draw: y - h' gamma
# given eta is normal with this `mean` and covariance `cov` (emulator,
# discrepancy and noise). On a grid design, with w = Kt^-1 k0, s = k0' w and
# a the nugget: mean E w and covariance c Kx / lambda_eta + Sigma_delta +
# diag(noise) / lambda_e, c = 1 + a - s (never forming Sigma_z); otherwise from the
# blocks of Sigma_z. Also returns the pieces the grid conditional reuses.
field_given_runs <- function(g, par, dg = draw_geometry(g, par)) {
  if (is_grid(g)) {
    r_t <- chol(jittered_cor(g$tt, dg$bt, par$nugget))
    v <- backsolve(r_t, dg$k0, transpose = TRUE)
    s <- sum(v^2)
    kx <- jittered_cor(g$xx, dg$bx, par$nugget)
    c_t <- 1 + par$nugget - s
    f <- g$field
    cov <- c_t * kx[f, f] / par$lambda_eta + delta_cov(g$ff, par)
    cov <- cov + noise_cov(g, par)
    mean_x <- drop(g$E %*% backsolve(r_t, v))
    return(list(mean = mean_x[f], cov = cov, kx = kx, mean_x = mean_x, s = s, c = c_t))
  }
  sigma <- koh_sigma_z(g, par, dg)
  f <- seq_len(g$n)
  r_c <- chol(sigma[-f, -f])
  a <- backsolve(r_c, t(sigma[f, -f, drop = FALSE]), transpose = TRUE)
  list(mean = drop(crossprod(a, backsolve(r_c, g$eta, transpose = TRUE))),
       cov = sigma[f, f] - crossprod(a))
}

# Grid design, in two steps: given the runs E at the grid inputs X, the
# emulator at rows u, v at tf has mean kx(u, X) Kx^-1 E w and covariance
# ((1 + a) kx(u, v) - s kx(u, X) Kx^-1 kx(X, v)) / lambda_eta (see
# field_given_runs()), and covariance c kx(u, xf) / lambda_eta with the field
# outputs; the new rows are then conditioned on y. Cost O(mt^3 + n_x^3) per
# draw.
koh_conditional_grid <- function(g, par) {
  dg <- draw_geometry(g, par)
  fm <- field_given_runs(g, par, dg)
  r_x <- chol(fm$kx)
  kx_sf <- jittered_cor(g$sf, dg$bx, par$nugget)
  u <- backsolve(r_x, t(jittered_cor(g$sx, dg$bx, par$nugget)), transpose = TRUE)
  mean_eta <- drop(crossprod(u, backsolve(r_x, fm$mean_x, transpose = TRUE)))
  prior <- new_rows_cov(g, dg, par)
  eta_rows <- seq_len(nrow(kx_sf))
  prior[eta_rows, eta_rows] <- prior[eta_rows, eta_rows] - fm$s * crossprod(u) / par$lambda_eta
  r_y <- chol(fm$cov)
  gain <- backsolve(r_y, t(rbind(fm$c * kx_sf / par$lambda_eta, delta_cov(g$sf, par))),
                    transpose = TRUE)
  h <- backsolve(r_y, field_y(g, par) - fm$mean, transpose = TRUE)
  list(mean = c(mean_eta, rep(0, length(eta_rows))) + drop(crossprod(gain, h)),
       cov = prior - crossprod(gain))
}

# Exact leave-one-out log predictive densities of the field outputs for one
# draw: log p(y_i | y_-i, eta), from the precision Q of y given the runs:
# y_i | y_-i ~ N(y_i - (Q r)_i / Q_ii, 1 / Q_ii) with r = y - mean.
loo_log_density <- function(g, par) {
  g <- residual_geometry(g, par)
  fm <- field_given_runs(g, par)
  q <- chol2inv(chol(fm$cov))
  qr <- drop(q %*% (field_y(g, par) - fm$mean))
  qd <- diag(q)
  -0.5 * log(2 * pi) + 0.5 * log(qd) - 0.5 * qr^2 / qd
}

# One draw from N(mean, cov) for a covariance that may be singular to
# rounding, through its Cholesky factor with the smallest jitter on the
# diagonal (from 1e-12 of the largest variance up) that makes it positive
# definite. Unlike eigenvectors, whose signs LAPACK builds choose
# differently, the factor is a continuous function of `cov`, so a seed gives
# the same draws on every machine (to rounding).
rmvnorm_psd <- function(mean, cov) {
  drop(mean + crossprod(jittered_chol(cov), stats::rnorm(length(mean))))
}

jittered_chol <- function(cov) {
  scale <- max(diag(cov), .Machine$double.xmin)
  for (jitter in c(0, 10^seq(-12, -6))) {
    r <- suppressWarnings(tryCatch(chol(cov + diag(jitter * scale, nrow(cov))),
                                   error = function(e) NULL))
    if (!is.null(r)) {
      return(r)
    }
  }
  abort_bayesbem(c("A predictive covariance is not positive semi-definite.",
                   i = "Its smallest eigenvalue is {signif(min(eigen(cov, TRUE, TRUE)$values), 3)} (largest variance {signif(scale, 3)})."),
                 "numerical")
}
