#' Name the cause of the discrepancy
#'
#' Ranks candidate explanations of what the simulator misses. The candidates
#' are the observable inputs and every column of `covariates`: anything known
#' per field row that the simulator does not use (occupancy, working days, a
#' calendar flag, a meter or equipment change, ...).
#'
#' For every posterior draw, the simulator residual `y - eta(x, tf)` at the
#' field rows is regressed on each candidate (linear and quadratic terms; a
#' linear term for two-valued candidates such as a step at a date).
#'
#' Part of any residual is not the simulator's fault: calibration parameters
#' that are off move the output along the simulator's own sensitivities
#' (e.g. a wrong infiltration rate leaves a residual that follows outdoor
#' temperature), and no hidden mechanism is needed to explain that. So both
#' the residual and the candidate are first made orthogonal to what
#' recalibration can do: a constant and, per calibration parameter, the
#' direction in which `eta` at the field rows moves with it (the covariance
#' of the `eta` draws with the `tf` draws). The candidate's `share` is the
#' fraction of the remaining residual variance it explains (a partial R^2),
#' summarised over draws by its mean and a central interval. A candidate
#' that only mimics a parameter's effect gets a share near zero: the data
#' cannot tell it from parameter error.
#'
#' Chance is accounted for by permutation: the partial R^2 of the posterior
#' mean residual is compared with its distribution when the candidate's
#' values are shuffled over the field rows, which gives a p-value per
#' candidate; the p-values are adjusted for the number of candidates by
#' Holm's method. A candidate `explains` the discrepancy when its adjusted
#' p-value is below `alpha`. The verdict names the best-ranked candidate that
#' explains it, or says that none does: for a correct simulator, that
#' happens in about `1 - alpha` of data sets.
#'
#' @param fit A `koh_fit`.
#' @param covariates Optional data frame with one row per field row (in the
#'   field data's order) of further candidates.
#' @param level Probability of the central interval of each share.
#' @param alpha Family-wise error rate of the "explains" decisions.
#' @param n_perm Number of permutations per candidate.
#' @param ndraws Number of posterior draws (evenly spaced); all by default.
#' @param seed Random seed of the permutations and of the residual draws.
#' @return A data frame of class `koh_explanation`, ranked by `share`:
#'   `candidate`, `share`, `lower`, `upper` (fractions), `p_value` (Holm
#'   adjusted), `explains`; the verdict is in `attr(, "verdict")`.
#' @family discrepancy
#' @export
#' @examples
#' working <- data.frame(working_days = c(22, 20, 21, 22, 22, 20, 23, 21, 21, 23, 20, 21))
#' explain_discrepancy(seb_fit, working, ndraws = 100, n_perm = 200, seed = 1)
explain_discrepancy <- function(fit, covariates = NULL, level = 0.9, alpha = 0.05,
                                n_perm = 1000, ndraws = NULL, seed = NULL) {
  check_koh_fit(fit)
  check_count(n_perm)
  check_probability(level)
  check_probability(alpha)
  candidates <- explanation_candidates(fit$data, covariates)
  with_seed(seed, {
    draws <- predict_draws(fit, field_inputs(fit$data), ndraws = ndraws)
    residual <- t(fit$data$field[[fit$data$names$y]] - t(draws$eta))
    nuisance <- qr(recalibration_basis(draws$eta, draws$tf))
    rows <- lapply(names(candidates), function(name) {
      explained_share(candidates[[name]], residual, nuisance, level, n_perm)
    })
  })
  out <- data.frame(candidate = names(candidates), do.call(rbind, rows))
  out$p_value <- stats::p.adjust(out$p_value, method = "holm")
  out$explains <- out$p_value < alpha
  out <- out[order(-out$share), ]
  rownames(out) <- NULL
  structure(out, class = c("koh_explanation", "data.frame"), level = level, alpha = alpha,
            verdict = explanation_verdict(out, level))
}

# The observable inputs and the covariates, checked.
explanation_candidates <- function(data, covariates, call = rlang::caller_env()) {
  candidates <- data$field[data$names$x]
  if (!is.null(covariates)) {
    covariates <- covariate_table(covariates, data$n, call = call)
    check_numeric_complete(covariates, names(covariates), "covariates", call = call)
    clash <- intersect(names(covariates), names(candidates))
    if (length(clash) > 0L) {
      abort_bayesbem("{.arg covariates} repeats the observable input{?s} {.field {clash}}; rename or drop {?it/them}.",
                     "columns", call = call)
    }
    candidates <- cbind(candidates, covariates)
  }
  check_columns_vary(candidates, call = call)
  candidates
}

# What recalibration can do to the output at the field rows (n x (1 + q)):
# a constant, and the covariance of the eta draws (S x n) with each column
# of the tf draws (S x q). Its column span is that of the regression slopes
# of eta on tf, without inverting the (often near-singular) tf covariance.
recalibration_basis <- function(eta, tf) {
  centre <- function(m) sweep(m, 2, colMeans(m))
  cbind(1, crossprod(centre(eta), centre(tf)))
}

# Share of the residual variance a candidate explains beyond recalibration
# (partial R^2 given the QR-decomposed `nuisance` basis): per draw (rows of
# `residual`), and a permutation p-value for the posterior mean residual.
explained_share <- function(v, residual, nuisance, level, n_perm) {
  basis <- function(u) {
    u <- (u - mean(u)) / stats::sd(u)
    b <- if (length(unique(u)) > 2L) cbind(u, u^2) else cbind(u)
    free <- qr.resid(nuisance, b)
    # a column inside the recalibration span is all rounding error: drop it
    free[, sqrt(colSums(free^2)) > 1e-8 * sqrt(colSums(b^2)), drop = FALSE]
  }
  r_squared <- function(u, r) {
    b <- basis(u)
    if (ncol(b) == 0L) {
      return(rep(0, NCOL(r)))
    }
    fitted <- qr.fitted(qr(b), r)
    colSums(as.matrix(fitted)^2) / colSums(as.matrix(r)^2)
  }
  free <- qr.resid(nuisance, t(residual))
  shares <- r_squared(v, free)
  mean_free <- rowMeans(free)
  observed <- r_squared(v, mean_free)
  null <- vapply(seq_len(n_perm), function(i) r_squared(sample(v), mean_free), numeric(1))
  interval <- stats::quantile(shares, c((1 - level) / 2, (1 + level) / 2), names = FALSE)
  data.frame(share = mean(shares), lower = interval[1], upper = interval[2],
             p_value = (1 + sum(null >= observed)) / (n_perm + 1))
}

explanation_verdict <- function(x, level) {
  cause <- x[x$explains, , drop = FALSE]
  if (nrow(cause) == 0L) {
    return("No candidate explains the discrepancy beyond chance.")
  }
  top <- cause[1, ]
  others <- if (nrow(cause) > 1L) {
    sprintf(" (also beyond chance: %s)", paste(cause$candidate[-1], collapse = ", "))
  } else {
    ""
  }
  sprintf("The discrepancy is best explained by %s: %.0f%% of the simulator residual (%g%% interval %.0f-%.0f%%, adjusted p = %.2g)%s.",
          top$candidate, 100 * top$share, 100 * level, 100 * top$lower, 100 * top$upper,
          top$p_value, others)
}

#' @export
print.koh_explanation <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(attr(x, "verdict"), "\n\n")
  print_rounded(as.data.frame(unclass(x)), digits)
  invisible(x)
}
