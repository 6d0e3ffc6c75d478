# What chance and recalibration produce (explain_discrepancy()): the
# residual given the runs, the null residuals simulated from the fitted
# model, the recalibration basis projected out, each term's normal
# score, the max-statistic p-values and the cross-validated gain.

# The geometry explain_discrepancy() needs: a fit with the basis emulator
# keeps it and the field rows' outputs, terms, noise weights and AR(1)
# segments, at a cost linear in the rows (no n x n pair of inputs); other
# fits the Gaussian-process geometry.
explanation_geometry <- function(fit) {
  data <- fit$data
  basis <- fit$emulator$basis
  if (is.null(basis)) {
    return(gp_geometry(data, NULL, fit_structure(fit)))
  }
  list(n = data$n, y = data$y, h = discrepancy_design(data), basis = basis,
       noise = noise_weights(data), segments = data_segments(data), months = fit_shifts(fit))
}

# For each draw of `pars`: the field outputs' residual from the emulator's
# mean given the runs (standardised, less any parametric discrepancy terms;
# `residual`, draws by rows) and, but for the basis emulator, the parts of
# its covariance without a discrepancy, averaged over the draws: the
# emulator's uncertainty given the runs (`emulator`) and the noise
# covariance (`noise`). The averages are summed as the draws come, so that
# one n x n matrix of each is held, not two per draw (8.5 GB for 4,000
# draws of a year of days).
residuals_given_runs <- function(g, pars) {
  if (!is.null(g$basis)) {
    residual <- vapply(pars, function(par) field_y(g, par) - basis_eta(g$basis, par$tf)$mean,
                       numeric(g$n))
    return(list(residual = t(residual)))
  }
  out <- list(residual = matrix(0, length(pars), g$n), emulator = 0, noise = 0)
  for (i in seq_along(pars)) {
    rg <- residual_geometry(g, pars[[i]])
    fm <- field_given_runs(rg, pars[[i]])
    noise <- noise_cov(g, pars[[i]])
    out$residual[i, ] <- field_y(rg, pars[[i]]) - fm$mean
    out$emulator <- out$emulator + (fm$cov - delta_cov(g$ff, pars[[i]]) - noise) / length(pars)
    out$noise <- out$noise + noise / length(pars)
  }
  out
}

# `n_null` residuals (columns) of the fitted model without any hidden
# effect, the emulator's part inflated by `kappa` (emulator_inflation()):
# N(0, kappa E + N), E and N the draws' mean covariances of
# residuals_given_runs(). With the basis emulator, at a cost linear in the
# rows, the j-th from the draws in turn: B (sqrt(kappa v(tf)) * z) plus
# noise of variance kappa s2r + w / lambda_e (white, or AR(1) within the
# segments; with a shift per month, the months' shifts from their prior), a
# mixture over the draws with the same covariance.
null_residuals <- function(g, pars, given_runs, kappa, n_null) {
  basis <- g$basis
  if (is.null(basis)) {
    cov <- kappa * given_runs$emulator + given_runs$noise
    return(crossprod(jittered_chol(cov), matrix(stats::rnorm(g$n * n_null), g$n)))
  }
  pc <- ncol(basis$B)
  sd_w <- matrix(vapply(pars, function(par) sqrt(kappa * basis_weights(basis, par$tf)$var),
                        numeric(pc)), pc)
  of <- (seq_len(n_null) - 1L) %% length(pars) + 1L
  emulator <- basis$B %*% (sd_w[, of, drop = FALSE] * stats::rnorm(pc * n_null))
  emulator + t(noise_matrix(pars[of], g$noise, g$segments, kappa * basis$s2r, g$months))
}

# How much the emulator understates its own error: the mean squared
# standardised error of each simulation run predicted from the others
# (leave one run out, at all its inputs), over up to 20 draws; 1 for a
# calibrated emulator, never below 1. Grid designs use the Kronecker form
# (the run's column of E given the other columns); others the precision
# matrix of the runs (block of each run's rows).
emulator_inflation <- function(g, pars) {
  if (!is.null(g$basis)) {
    return(basis_inflation(g$basis))
  }
  pars <- pars[draw_subset(length(pars), 20L)]
  kappa <- vapply(pars, function(par) {
    rg <- residual_geometry(g, par)
    dg <- draw_geometry(rg, par)
    kt <- jittered_cor(rg$tt, dg$bt, par$nugget)
    if (is_grid(rg)) {
      r_x <- chol(jittered_cor(rg$xx, dg$bx, par$nugget) / par$lambda_eta)
      z2 <- vapply(seq_len(ncol(rg$E)), function(a) {
        w <- solve(kt[-a, -a], kt[-a, a])
        r <- backsolve(r_x, rg$E[, a] - drop(rg$E[, -a] %*% w), transpose = TRUE)
        mean(r^2) / (kt[a, a] - sum(kt[-a, a] * w))
      }, numeric(1))
      return(mean(z2))
    }
    q <- chol2inv(chol(jittered_cor(rg$cc, dg$bx, par$nugget) * kt / par$lambda_eta))
    qe <- drop(q %*% rg$eta)
    runs <- split(seq_along(rg$eta), row_keys(rg$tc))
    mean(unlist(lapply(runs, function(a) {
      # leave-block-out error e = Q_AA^-1 (Q eta)_A, covariance Q_AA^-1
      r_a <- chol(q[a, a, drop = FALSE])
      (drop(r_a %*% solve(q[a, a, drop = FALSE], qe[a])))^2
    })))
  }, numeric(1))
  max(1, mean(kappa))
}

# The same for the basis emulator: the mean squared standardised error of
# each run's weights predicted by its component's Gaussian process fitted
# again without the run's fold (10-fold cross-validation over the runs,
# hyperparameters and all), over runs and components. Leave one run out
# with the hyperparameters held (Rasmussen & Williams 2006, Eq 5.12) is
# about 1 by construction of their maximum-likelihood fit, and does not see
# length scales too long for the runs: on the case-study EnergyPlus model
# by hour (60 runs, 14 components) it gave 0.96 where the errors at 40 new
# parameter points were 2.8 times the stated variance (this
# cross-validation: 2.4), and the nulls then raised false alarms.
basis_inflation <- function(basis, folds = 10L) {
  tc <- basis$tc
  fold <- (seq_len(nrow(tc)) - 1L) %% min(folds, nrow(tc)) + 1L
  z2 <- lapply(seq_along(basis$components), function(j) {
    unlist(lapply(unique(fold), function(f) {
      out <- fold == f
      kept <- tc[!out, , drop = FALSE]
      gp <- fit_component(kept, basis$w[!out, j])
      held <- vapply(which(out), function(a) component_moments(gp, kept, tc[a, ]), numeric(2))
      (basis$w[out, j] - held[1, ])^2 / pmax(held[2, ], .Machine$double.eps)
    }))
  })
  max(1, mean(unlist(z2)))
}

# What explain_discrepancy() judges a term against: the geometry (`g`),
# the posterior draws (`pars`, evenly spaced with `ndraws`), the field
# residuals given the runs at each draw (`given_runs`, residuals_given_runs())
# and the basis of what recalibration can do to them (`basis`).
recalibration_geometry <- function(fit, ndraws = NULL) {
  g <- explanation_geometry(fit)
  pars <- draw_parameters(fit, ndraws)
  given_runs <- residuals_given_runs(g, pars)
  tf <- do.call(rbind, lapply(pars, `[[`, "tf"))
  list(g = g, pars = pars, given_runs = given_runs,
       basis = recalibration_basis(-given_runs$residual, tf))
}

# What recalibration can do to the output at the field rows (n columns of
# a basis): a constant, the covariance of the eta draws (S x n) with each
# column of the centred tf draws (S x q), and then with their squares and
# products, while the basis has at most n / 3 columns. The first-order
# columns span the regression slopes of eta on tf without inverting the
# (often near-singular) tf covariance; the second-order ones, the output's
# curvature in the parameters (measured: an equipment or infiltration
# error moves heating and cooling months differently, so a linear
# correction leaves a step at the regime switch, which region terms then
# named in 6 of 19 data sets without a hidden effect).
recalibration_basis <- function(eta, tf) {
  centre <- function(m) sweep(m, 2, colMeans(m))
  tf <- centre(tf)
  q <- ncol(tf)
  pairs <- which(upper.tri(diag(q), diag = TRUE), arr.ind = TRUE)
  pairs <- pairs[order(pairs[, "row"] != pairs[, "col"]), , drop = FALSE]
  second <- tf[, pairs[, 1], drop = FALSE] * tf[, pairs[, 2], drop = FALSE]
  features <- cbind(tf, centre(second))
  keep <- seq_len(max(q, min(ncol(features), floor(ncol(eta) / 3) - 1L)))
  cbind(1, crossprod(centre(eta), features[, keep, drop = FALSE]))
}

# Share of the residual variance a term explains beyond recalibration
# (partial R^2 given the QR-decomposed `nuisance` basis): per draw (the
# columns of `free`, the draws' residuals made orthogonal to `nuisance`),
# summarised by their mean, with the interval of share_interval() over the
# `blocks` of periods (jackknife_blocks()); and the term's standing against
# chance (chance_z() of `mean_free`, the posterior mean residual's part
# orthogonal to `nuisance`, against the null residuals `null_free`,
# orthogonal to it too). The caller projects all three once for all terms.
term_scores <- function(b, free, mean_free, null_free, nuisance, level, blocks) {
  shares <- partial_r_squared(b, free, nuisance)
  chance <- chance_z(b, mean_free, null_free, nuisance)
  left_out <- vapply(blocks, function(k) {
    partial_r_squared(b[k$rows, , drop = FALSE], k$free, k$nuisance)
  }, numeric(1))
  interval <- share_interval(mean(shares), left_out, level)
  list(summary = data.frame(share = mean(shares), lower = interval[1], upper = interval[2],
                            z = chance$z),
       null_z = chance$null_z, shares = shares)
}

# R^2 of each column of `r` (already orthogonal to `nuisance`) by the
# columns of `b` made orthogonal to it too (free_columns()); 0 when none
# is left. The fitted part's squares are summed from Q'r (Q the
# orthonormal basis of the free columns), one matrix product for all
# columns of `r` (the null's thousand at a year of hours); their total
# sums of squares are with_totals()'s when `r` has them.
partial_r_squared <- function(b, r, nuisance) {
  b <- cbind(b)
  free_b <- qr.resid(nuisance, b)
  free_b <- free_b[, free_columns(b, nuisance, free_b), drop = FALSE]
  if (ncol(free_b) == 0L) {
    return(rep(0, NCOL(r)))
  }
  q <- qr(free_b)
  explained <- crossprod(qr.Q(q)[, seq_len(q$rank), drop = FALSE], r)
  colSums(explained^2) / (attr(r, "total") %||% colSums(as.matrix(r)^2))
}

# Residuals (columns) that many terms are scored on, with each column's
# sum of squares kept, not recomputed per term (at a year of hours a
# thousand columns of 8,760 rows: the square of that matrix cost more than
# the term's fit).
with_totals <- function(r) structure(r, total = colSums(r^2))

# The columns of a term that recalibration (`nuisance`) leaves at least a
# tenth of (in norm): a column 99 % inside what recalibration does (a
# region's step at the simulator's switch from heating to cooling) only
# adds a direction the data can hardly attribute, whose fit rests on a few
# rows; dropping it leaves, e.g., a line's slope. `free`: the columns'
# residuals, when the caller has them.
free_columns <- function(b, nuisance, free = qr.resid(nuisance, cbind(b))) {
  sqrt(colSums(free^2)) > 0.1 * sqrt(colSums(cbind(b)^2))
}

# A term's partial R^2 of the posterior mean residual (`free`) against the
# null residuals' (`null_free`, both orthogonal to `nuisance`), as normal
# scores: `z` = Phi^-1(F(R^2)) with F the Beta distribution of the null
# R^2's mean and variance, and the null residuals' own scores (for the
# max-statistic adjustment). A k-column term's R^2 of white noise is
# exactly Beta(k / 2, (n - k) / 2); matching the moments keeps terms of one
# and of two columns on one scale, which (R^2 - mean) / sd does not (one
# column's tail is the heavier, so it dominates the family's maximum).
chance_z <- function(b, free, null_free, nuisance) {
  reference <- partial_r_squared(b, null_free, nuisance)
  m <- mean(reference)
  common <- m * (1 - m) / max(stats::var(reference), .Machine$double.eps) - 1
  if (!(m > 0 && common > 0)) {
    # a term inside the recalibration span explains nothing, data or null
    return(list(z = 0, null_z = rep(0, length(reference))))
  }
  score <- function(r2) {
    -stats::qnorm(stats::pbeta(r2, m * common, (1 - m) * common, lower.tail = FALSE, log.p = TRUE),
                  log.p = TRUE)
  }
  list(z = score(partial_r_squared(b, free, nuisance)), null_z = score(reference))
}

# The posterior mean residual without each block of consecutive periods
# in turn, beyond recalibration on the remaining rows: `rows` kept, the QR
# `nuisance` of their recalibration basis and the residual's `free` part.
# Blocks of about n^(1/3) periods (the block length of Kunsch's 1989
# moving-block bootstrap), so that a left-out period's autocorrelated
# neighbours go with it, and at most 100 blocks (a grouped jackknife:
# above 1,000 rows longer blocks, 88 hours at a year of hours, so that
# the cost stays linear in the rows).
jackknife_blocks <- function(basis, mean_residual) {
  n <- length(mean_residual)
  size <- max(1L, round(n^(1 / 3)), ceiling(n / 100))
  lapply(split(seq_len(n), ceiling(seq_len(n) / size)), function(out) {
    rows <- setdiff(seq_len(n), out)
    q <- qr(basis[rows, , drop = FALSE])
    list(rows = rows, nuisance = q, free = qr.resid(q, mean_residual[rows]))
  })
}

# The interval of a share from its values without each of g blocks
# (delete-a-block jackknife, Kunsch 1989): share -/+ z se, se^2 = (g - 1) /
# g * sum((s_i - mean(s))^2), within [0, 1]. How much the share rests on
# particular periods: the posterior draws alone differ only in what
# recalibration absorbs, so their spread is no interval of the share.
share_interval <- function(share, left_out, level) {
  g <- length(left_out)
  se <- sqrt((g - 1) / g * sum((left_out - mean(left_out))^2))
  z <- stats::qnorm((1 + level) / 2)
  c(max(share - z * se, 0), min(share + z * se, 1))
}

# Sum of squared leave-one-out errors of the least squares fit of r on the
# columns of x; Inf when a row is fitted exactly (leverage 1).
press <- function(x, r) {
  q <- qr(x)
  h <- rowSums(qr.Q(q)[, seq_len(q$rank), drop = FALSE]^2)
  if (any(h > 1 - 1e-8)) return(Inf)
  sum((qr.resid(q, r) / (1 - h))^2)
}

# How much better the posterior mean residual is predicted out of sample
# with the term than by recalibration alone: 1 - PRESS(basis, b) /
# PRESS(basis), PRESS the sum of squared leave-one-out errors of the least
# squares fit, e_i / (1 - h_ii). Positive when the term predicts left-out
# rows (a term that only fits noise, or a few rows, makes PRESS larger).
# The term's columns as free_columns() keeps them (`nuisance`, qr(basis),
# factored once by the caller for all terms); 0 when none is left. A
# `line` (its step, then its slope) predicts when it or its slope alone
# does.
cv_gain <- function(r, basis, b, baseline = press(basis, r), line = FALSE,
                    nuisance = qr(basis)) {
  gain <- function(columns) {
    columns <- columns[, free_columns(columns, nuisance), drop = FALSE]
    if (ncol(columns) == 0L) 0 else 1 - press(cbind(basis, columns), r) / baseline
  }
  b <- cbind(b)
  if (line) max(gain(b), gain(b[, 2, drop = FALSE])) else gain(b)
}

# The share of alpha each family of terms gets when regions are tried: the
# main terms keep most of it; the many region terms, whose null is the
# less certain (the emulator's error at a regime switch is step-shaped and
# not in it), a fifth (chosen by measurement, bench/results/).
region_weights <- c(main = 0.8, region = 0.2)

# Adjusted p-values: within each family of terms, the max-statistic
# adjustment of Westfall and Young (a term's score `z` against
# the largest over the family's terms in each null residual), divided by
# the family's share of alpha (weighted Bonferroni across families), so
# that naming terms with p < alpha keeps the family-wise error rate at
# alpha over all terms.
adjusted_p_values <- function(scores, family, weights) {
  z <- vapply(scores, function(s) s$summary$z, numeric(1))
  p <- numeric(length(z))
  for (f in unique(family)) {
    in_f <- family == f
    null_max <- do.call(pmax, lapply(scores[in_f], `[[`, "null_z"))
    exceed <- vapply(z[in_f], function(v) sum(null_max >= v), numeric(1))
    p[in_f] <- pmin(1, (1 + exceed) / (length(null_max) + 1) / weights[[f]])
  }
  p
}

# The smallest adjusted p-value of a family is 1 / (n_null + 1) / weight
# (adjusted_p_values()); with fewer null residuals than make it fall below
# alpha, no term of that family could ever be named.
check_null_size <- function(n_null, alpha, weights, call = rlang::caller_env()) {
  share <- min(weights)
  needed <- floor(1 / (alpha * share) - 1 + 1e-8) + 1
  if (n_null >= needed) {
    return(invisible(n_null))
  }
  hint <- if (length(weights) > 1) {
    c(i = "Regions get {share} of {.arg alpha}: an adjusted p-value is at least 1 / ({.arg n_null} + 1) / {share}.",
      i = "Increase {.arg n_null}, or set {.code regions = FALSE}.")
  } else {
    c(i = "An adjusted p-value is at least 1 / ({.arg n_null} + 1).", i = "Increase {.arg n_null}.")
  }
  abort_bayesbem(c("{.arg n_null} must be at least {needed} for a term to pass {.arg alpha} = {alpha}, not {n_null}.",
                   hint), "argument", call = call)
}
