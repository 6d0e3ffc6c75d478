# Conditionals of a fit with the additive discrepancy (R/gp-hsgp.R) at a
# cost linear in the rows, as koh_basis.stan's likelihood: with the basis
# emulator the field outputs are
#   y - mu - h' gamma = U a + e,  U = [B, Phi, M],  a = (w, b, l),
#   w ~ N(w(tf), diag(v(tf))),  b ~ N(0, diag(S)),  l ~ N(0, I / lambda_shift),
#   e ~ N(0, d I),
# d = s2r + noise / lambda_e (the truncated components and the noise; with
# AR(1) noise both AR(1) over consecutive rows, e ~ N(0, d R); M the rows'
# month indicators and l the months' shifts with a shift per month, none
# otherwise), so given the data a is normal in pc + m p (+ months)
# dimensions, whatever the rows. With c = (v, S, 1 / lambda_shift), s =
# sqrt(c), a = a0 + diag(s) z and a0 = (w(tf), 0, 0), z has
# precision A = I + diag(s) U'U diag(s) / d and mean A^-1 diag(s) U'(r - U
# a0) / d, r = y - mu - h' gamma (Rasmussen & Williams 2006, Eq 2.8 on the
# weights; the scaling by s keeps A well conditioned where a component's
# variance vanishes; with AR(1) noise U'U and U'r are weighted by R^-1).
# The emulator at a field row is mu + B w plus its truncated components t,
# given a and the data t ~ N(s2r / d (r - U a), s2r (1 - s2r / d) R), R = I
# without AR(1) noise; the discrepancy at any
# inputs is Phi(x) b. The basis emulator knows the simulator at the field
# rows only: elsewhere the simulator runs (predict_scenario()).

# Whether a fit's discrepancy is the additive Hilbert-space one.
is_additive <- function(fit) identical(fit$settings$discrepancy_kernel, "additive")

# The parts of the conditionals that no draw changes: the basis emulator,
# the Hilbert-space design, U at the field rows, the Gram matrix of Z = [U,
# r0, h] (r0 = y - mu, h the discrepancy terms, U's last columns the rows'
# months with a shift per month) and, with AR(1) noise, the field rows'
# segments and ar1_grams() of Z.
additive_geometry <- function(fit) {
  data <- fit$data
  basis <- fit$emulator$basis
  design <- fit$settings$hsgp
  r0 <- data$y - basis$mu
  h <- discrepancy_design(data)
  shifts <- fit_shifts(fit)
  months <- if (!is.null(shifts)) shift_columns(shifts)
  z <- hsgp_columns(basis$B, field_grid_inputs(data), r0, h, design, months)
  u <- z[, seq_len(ncol(z) - 1L - ncol(h)), drop = FALSE]
  segments <- fit_segments(fit)
  list(basis = basis, design = design, pc = ncol(basis$B), months = colnames(months),
       u = u, gram = crossprod(z),
       ar = if (!is.null(segments)) ar1_grams(z, segments), segments = segments,
       r0 = r0, h = h, noise = noise_weights(data))
}

# The normal law of a given the data for one draw: `a0`, `s`, `d`, the
# upper Cholesky factor `r` of A and the mean `z` of z (see the top), with
# U'U, U'r0 and U'h weighted by R^-1 under AR(1) noise.
additive_posterior <- function(ag, par) {
  wv <- basis_weights(ag$basis, par$tf)
  s <- sqrt(c(wv$var, hsgp_spectral(ag$design, par$beta_delta, par$lambda_delta),
              rep(1 / par$lambda_shift, length(ag$months))))
  d <- ag$basis$s2r + ag$noise[1] / par$lambda_e
  a0 <- c(wv$mean, numeric(length(s) - ag$pc))
  g <- if (is.null(ag$ar)) ag$gram else ar1_weighted(ag$gram, ag$ar, par$phi)
  u <- seq_along(s)
  uu <- g[u, u, drop = FALSE]
  ue <- g[u, length(s) + 1] - drop(g[u, -c(u, length(s) + 1), drop = FALSE] %*% par$gamma) -
    drop(uu %*% a0)
  r <- chol(diag(length(s)) + outer(s, s) * uu / d)
  z <- backsolve(r, backsolve(r, s * ue / d, transpose = TRUE))
  list(a0 = a0, s = s, d = d, r = r, z = z)
}

# One joint draw of the emulator at the field rows `at` (indices; none
# with integer(0)), of the discrepancy's Gaussian-process part at new
# inputs, whose basis functions are `phi_new` (hsgp_phi()), and of the
# training months' shifts, for one draw of the parameters.
additive_draw <- function(ag, par, at, phi_new) {
  post <- additive_posterior(ag, par)
  z <- post$z + backsolve(post$r, stats::rnorm(length(post$z)))
  a <- post$a0 + post$s * z
  w <- seq_len(ag$pc)
  l <- length(a) - length(ag$months) + seq_along(ag$months)
  delta <- drop(phi_new %*% a[-c(w, l)])
  shift <- stats::setNames(a[l], ag$months)
  if (length(at) == 0L) {
    return(list(eta = numeric(0), delta = delta, shift = shift))
  }
  # t at every field row, then the rows asked for (a row asked twice, one t)
  s2r <- ag$basis$s2r
  e <- ag$r0 - drop(ag$h %*% par$gamma) - drop(ag$u %*% a)
  spread <- if (is.null(ag$segments)) stats::rnorm(length(e)) else
    ar1_series(par$phi, ag$segments)
  truncated <- s2r / post$d * e + sqrt(s2r * (1 - s2r / post$d)) * spread
  eta <- ag$basis$mu + drop(ag$basis$B %*% a[w]) + truncated
  list(eta = eta[at], delta = delta, shift = shift)
}

# Draws (rows) by new rows (columns) of eta and delta, scaled, for the
# parameter draws `pars` (`x_new`: newdata's inputs scaled); eta (NA
# otherwise) when `types` has "y" or "eta", which needs every row of
# `newdata` to be a field row's inputs; and by the training months, their
# shifts (`shift`, none without a shift per month).
additive_joint <- function(fit, newdata, pars, types = c("y", "eta"),
                           x_new = scale_newdata(fit$data, newdata, call = call),
                           call = rlang::caller_env()) {
  with_eta <- any(c("y", "eta") %in% types)
  at <- if (with_eta) field_row_of(fit$data, newdata, call = call) else integer(0)
  ag <- additive_geometry(fit)
  phi_new <- hsgp_phi(x_new, ag$design)
  draws <- lapply(pars, additive_draw, ag = ag, at = at, phi_new = phi_new)
  delta <- do.call(rbind, lapply(draws, `[[`, "delta"))
  eta <- if (with_eta) do.call(rbind, lapply(draws, `[[`, "eta")) else NA * delta
  shift <- do.call(rbind, lapply(draws, `[[`, "shift"))
  list(eta = eta, delta = delta, shift = shift)
}

# The field row with the inputs of each row of `newdata` (to 6 significant
# digits); an error naming the first row that has none.
field_row_of <- function(data, newdata, call = rlang::caller_env()) {
  x <- data$names$x
  at <- match(value_keys(newdata[x]), value_keys(data$field[x]))
  if (anyNA(at)) {
    abort_bayesbem(c("This fit knows the simulator only at its field rows; row {which(is.na(at))[1]} of {.arg newdata} is not one of them.",
                     i = "Its emulator is the principal components of the runs there (the additive discrepancy). Predict elsewhere through the simulator ({.fn predict_scenario}), or ask for {.code type = \"delta\"}, the discrepancy alone."),
                   "newdata", call = call)
  }
  at
}
