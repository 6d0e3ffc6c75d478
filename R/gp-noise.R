# The observation noise's covariance and draws, for one draw `par` of the
# parameters: var(e_i) = w_i / lambda_e (the weights w_i of
# R/data-noise.R), AR(1) correlation within segments of consecutive rows,
# and a shift per calendar month.

# Each field row's noise variance for one draw `par` of a fit whose
# geometry `g` (gp_geometry()) holds the rows' weights.
noise_var <- function(g, par) g$noise / par$lambda_e

# The field rows' noise covariance for one draw: diag(noise_var()), or with
# the draw's AR(1) coefficient phi, scaled by its correlation within the
# rows' segments (`g$segments`); `extra`: a variance per row that shares
# it (the basis emulator's truncated components).
noise_cov <- function(g, par, extra = 0) {
  v <- extra + noise_var(g, par)
  phi <- par$phi %||% 0
  if (phi == 0) {
    return(diag(v, length(v)))
  }
  ar1_cor(phi, g$segments) * outer(sqrt(v), sqrt(v))
}

# AR(1) noise (calibrate(noise_correlation = "ar1")): the errors of
# consecutive periods correlate, e_i = phi e_(i-1) + sqrt(1 - phi^2) nu_i,
# of stationary variance w / lambda_e (Box & Jenkins; its correlation
# matrix R has phi^|i - j| within a run of consecutive periods, its
# inverse is tridiagonal), within the segments of consecutive rows that
# noise_segments() finds.

# AR(1)'s correlation matrix over rows in segments: phi^|i - j| within one.
ar1_cor <- function(phi, segments) {
  i <- seq_along(segments)
  phi^abs(outer(i, i, "-")) * outer(segments, segments, "==")
}

# Observation noise N(0, w_i / lambda_e), standardised: draws (rows) by
# periods of weights `w` (columns); with a draw's AR(1) coefficient `phi`,
# correlated within `segments` (noise_segments() of the periods). `extra`:
# a variance per period that shares it (as noise_cov()'s). With the
# periods' `months` (a shift per month), each month's shift added
# (shift_matrix(), the training months' from `known`).
noise_matrix <- function(draws, w, segments = NULL, extra = 0, months = NULL, known = NULL) {
  lambda_e <- vapply(draws, `[[`, numeric(1), "lambda_e")
  phi <- vapply(draws, function(par) par$phi %||% 0, numeric(1))
  z <- if (all(phi == 0)) {
    matrix(stats::rnorm(length(draws) * length(w)), length(draws))
  } else {
    t(vapply(phi, ar1_series, numeric(length(w)), segments = segments))
  }
  e <- z * sqrt(extra + outer(1 / lambda_e, w))
  if (is.null(months)) e else e + shift_matrix(draws, months, known)
}

# The products a likelihood with AR(1) noise needs of the rows of z, given
# their segments: `lag` = z'(S + S')z, S the lag-1 shift within segments,
# `end` = z'Ez over the segments' first and last rows (a one-row segment's
# twice) and the number of `segments`; then (1 - phi^2) z'R^-1 z = (1 +
# phi^2) z'z - phi^2 end - phi lag.
ar1_grams <- function(z, segments) {
  n <- nrow(z)
  lo <- which(segments[-1] == segments[-n])
  cross <- crossprod(z[lo, , drop = FALSE], z[lo + 1L, , drop = FALSE])
  ends <- c(which(!duplicated(segments)), which(!duplicated(segments, fromLast = TRUE)))
  list(lag = cross + t(cross), end = crossprod(z[ends, , drop = FALSE]),
       segments = length(unique(segments)))
}

# z'R^-1 z from z'z (`gram`) and ar1_grams() `ar`, for coefficient phi.
ar1_weighted <- function(gram, ar, phi) {
  if (phi == 0) {
    return(gram)
  }
  ((1 + phi^2) * gram - phi^2 * ar$end - phi * ar$lag) / (1 - phi^2)
}

# A unit-variance AR(1) series over rows in segments, restarted
# (stationary) at each segment's first row.
ar1_series <- function(phi, segments) {
  nu <- stats::rnorm(length(segments))
  if (phi == 0) {
    return(nu)
  }
  first <- !duplicated(segments)
  nu[!first] <- sqrt(1 - phi^2) * nu[!first]
  unlist(lapply(split(nu, segments), function(v) {
    as.numeric(stats::filter(v, phi, method = "recursive"))
  }), use.names = FALSE)
}

# A shift per calendar month (calibrate(noise_shift = "month")): the
# errors of output k add l_m(i) to the AR(1) (or white) noise of each row i
# of month m(i), l_m ~ N(0, 1 / lambda_shift) independent between months,
# so that a month's total carries the month's shift (a meter's use that
# moves month by month beyond what the inputs explain). The shifts are
# U's further columns in the additive likelihood (koh_basis.stan), the
# rows' indicators of their months: no cost in the rows.

# The rows' indicators (rows by `months`) of their months `labels`.
shift_columns <- function(labels, months = sort(unique(labels))) {
  m <- outer(labels, months, "==") + 0
  colnames(m) <- months
  m
}

# Each draw's (rows) month shift at each period of months `labels`
# (columns), standardised: a month among the columns of `known` (draws by
# months, the fit's training months given the data) takes its draw there,
# any other month a draw from N(0, 1 / lambda_shift), one per month and
# draw, shared by the month's periods.
shift_matrix <- function(draws, labels, known = NULL) {
  months <- unique(labels)
  sd <- 1 / sqrt(vapply(draws, `[[`, numeric(1), "lambda_shift"))
  shifts <- vapply(months, function(m) {
    if (m %in% colnames(known)) known[, m] else stats::rnorm(length(sd), 0, sd)
  }, numeric(length(sd)))
  shifts <- matrix(shifts, nrow = length(sd), dimnames = list(NULL, months))
  shifts[, labels, drop = FALSE]
}
