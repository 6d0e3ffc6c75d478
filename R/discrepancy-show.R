#' Where the simulator is wrong: the posterior discrepancy
#'
#' For every field point, the posterior of what the simulator misses, in
#' physical units and as a share of the measured output: the model
#' discrepancy `delta(x)`, and the simulator residual `y - eta(x, tf)`
#' (discrepancy plus noise). Points are flagged with a simultaneous band of
#' the residual, so that looking at n points at once does not find some by
#' chance: the band is `mean +/- c sd` at every point, with `c` the
#' order statistic (of rank `ceiling((n + 1) level)` of n draws) of the
#' largest standardised deviation
#' `max_i |r_i - mean_i| / sd_i` (a max-statistic band, which contains the
#' whole residual vector with probability `level`). The global check comes
#' first: the simulator is consistent with the data when the band contains
#' zero everywhere; otherwise the points where it excludes zero are
#' flagged. There the simulator, at its calibrated parameters, misses the
#' measurement by more than the model's uncertainty. (The interval of
#' `delta` alone is often wider, because the calibration parameters can
#' trade a shift of the output against the discrepancy.) The verdict names
#' the flagged points and the sign: a positive residual means the simulator
#' under-predicts.
#'
#' Shares are percentages of the measured output, with outputs smaller than
#' a tenth of the mean absolute output counted as a tenth of it, so that
#' points with almost no use (gas in summer) do not get enormous or infinite
#' shares.
#'
#' @param fit A `bayesbem_fit`; on several outputs, each output's
#'   discrepancy on its field data, with a first column `output`.
#' @param newdata,obs Observable inputs and measured outputs to examine;
#'   default: the field data the model was calibrated on (on several
#'   outputs, given output by output on [output_fit()]).
#' @param level Probability of the pointwise intervals and of the
#'   simultaneous band.
#' @template args-ndraws
#' @return A data frame of class `bayesbem_discrepancy`, one row per point: the
#'   inputs, `point`, `obs`, and for `delta` and `residual` the posterior
#'   `mean`, pointwise `lower` and `upper` (physical units) and `share`
#'   (mean, percent of `obs`, see Details), the residual's simultaneous band
#'   `band_lower`, `band_upper`, and `flag` (the band excludes zero). The
#'   verdict is in `attr(, "verdict")`, the band's multiplier `c` in
#'   `attr(, "critical")`.
#' @family discrepancy
#' @export
#' @examples
#' d <- discrepancy(seb_fit, ndraws = 200)
#' d
#' plot_discrepancy(d)
discrepancy <- function(fit, newdata = NULL, obs = NULL, level = 0.9, ndraws = NULL) {
  check_fit(fit)
  check_probability(level)
  UseMethod("discrepancy")
}

#' @export
discrepancy.bayesbem_fit <- function(fit, newdata = NULL, obs = NULL, level = 0.9, ndraws = NULL) {
  if (!is.null(newdata) && is.null(obs)) {
    abort_bayesbem("Give {.arg obs}, the measured outputs at {.arg newdata}.", "argument")
  }
  set <- prediction_set(fit, newdata, obs)
  draws <- predict_draws(fit, set$x, ndraws = ndraws)
  residual <- -sweep(draws$eta, 2, set$obs, "-")
  delta_int <- column_intervals(draws$delta, level)
  residual_int <- column_intervals(residual, level)
  band <- simultaneous_band(residual, level)
  share_of <- share_scale(set$obs)
  out <- data.frame(
    set$x[fit$data$names$x], point = seq_along(set$obs), obs = set$obs,
    delta_mean = colMeans(draws$delta), delta_lower = delta_int[, 1], delta_upper = delta_int[, 2],
    delta_share = 100 * colMeans(draws$delta) / share_of,
    residual_mean = colMeans(residual), residual_lower = residual_int[, 1],
    residual_upper = residual_int[, 2], residual_share = 100 * colMeans(residual) / share_of,
    band_lower = band$lower, band_upper = band$upper,
    row.names = NULL
  )
  out$flag <- out$band_lower > 0 | out$band_upper < 0
  structure(out, class = c("bayesbem_discrepancy", "data.frame"), level = level,
            critical = band$critical, verdict = discrepancy_verdict(out, level))
}

# discrepancy() of each output of a fit on several outputs, on its field
# data, stacked with a first column `output`; each output's band is its own
# (`attr(, "critical")` by output), the verdict one line per output.
#' @export
discrepancy.bayesbem_fit_outputs <- function(fit, newdata = NULL, obs = NULL, level = 0.9,
                                             ndraws = NULL) {
  each <- output_results(fit, discrepancy, list(newdata = newdata, obs = obs),
                         level = level, ndraws = ndraws)
  parts <- each$results
  structure(each$table, class = c("bayesbem_discrepancy", "data.frame"), level = level,
            critical = vapply(parts, attr, numeric(1), "critical"),
            verdict = paste(sprintf("%s: %s", names(parts), vapply(parts, attr, "", "verdict")),
                            collapse = "\n"))
}

# Simultaneous band of the columns of a draws matrix: mean +/- c sd, with c
# the order statistic of the draws' max_i |x_i - mean_i| / sd_i that a new
# draw's stays below with probability >= `level` (covering_rank()).
simultaneous_band <- function(draws, level) {
  centre <- colMeans(draws)
  spread <- pmax(apply(draws, 2, stats::sd), .Machine$double.eps)
  deviation <- abs(sweep(sweep(draws, 2, centre), 2, spread, "/"))
  largest <- apply(deviation, 1, max)
  critical <- sort(largest)[covering_rank(length(largest), level)]
  list(lower = centre - critical * spread, upper = centre + critical * spread,
       critical = critical)
}

# Denominators of the shares: the measured output, but at least a tenth of
# the mean absolute output.
share_scale <- function(obs) {
  pmax(abs(obs), 0.1 * mean(abs(obs)))
}

discrepancy_verdict <- function(d, level) {
  flagged <- d[d$flag, , drop = FALSE]
  if (nrow(flagged) == 0L) {
    return(sprintf("The simulator is consistent with the data: the %g%% simultaneous band of y - eta contains zero at every point.",
                   100 * level))
  }
  # the points named, up to ten (hourly data flag thousands)
  describe <- function(rows, word) {
    if (nrow(rows) == 0L) return(NULL)
    named <- if (nrow(rows) == 1L) paste("point", rows$point) else if (nrow(rows) <= 10L)
      paste("points", paste(rows$point, collapse = ", ")) else
      sprintf("%d points, the first %s", nrow(rows), paste(utils::head(rows$point, 5L), collapse = ", "))
    sprintf("%s at %s (by %s%% of the output on average)", word, named,
            format(mean(abs(rows$residual_share)), digits = 2))
  }
  parts <- c(describe(flagged[flagged$residual_mean > 0, ], "under-predicts"),
             describe(flagged[flagged$residual_mean < 0, ], "over-predicts"))
  sprintf("The simulator is wrong at %d of %d points: it %s.", nrow(flagged), nrow(d),
          paste(parts, collapse = "; it "))
}

#' @export
print.bayesbem_discrepancy <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(attr(x, "verdict"), "\n\n")
  print_rounded(as.data.frame(unclass(x)), digits)
  invisible(x)
}
