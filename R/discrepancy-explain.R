#' Name the cause of the discrepancy
#'
#' Ranks candidate explanations of what the simulator misses. The candidates
#' are the observable inputs and every column of `covariates`: anything known
#' per field row that the simulator does not use (occupancy, working days, a
#' calendar flag, a meter or equipment change, ...).
#'
#' For every posterior draw, the simulator residual `y - eta(x, tf)` at the
#' field rows, with `eta` the emulator's mean given the simulation runs (not
#' given the field data, which would pull it towards `y` along the inputs),
#' is regressed on each candidate (linear and quadratic terms; a linear term
#' for two-valued candidates such as a step at a date). With `regions =
#' TRUE` (the default), effects that act in part of the input space are
#' candidates too, at each quartile, tertile and median of each observable input: a step
#' where the input passes it ("rh > 47"), hinges that grow past it ("max(temp
#' - 18, 0)", a balance point; "max(12 - temp, 0)"), and each other
#' candidate's line (offset and slope) only on one side of it ("rh, where
#' temp > 15": a latent load that grows with humidity once the building
#' cools), tested and cross-validated both as a line and as its slope
#' through zero (one column less to pay for when there is no offset).

#' Part of any residual is not the simulator's fault: calibration parameters
#' that are off move the output along the simulator's own sensitivities
#' (e.g. a wrong infiltration rate leaves a residual that follows outdoor
#' temperature), and no hidden mechanism is needed to explain that. So both
#' the residual and the candidate are first made orthogonal to what
#' recalibration can do: a constant and, per calibration parameter, the
#' direction in which `eta` at the field rows moves with it (the covariance
#' of the `eta` draws with the `tf` draws), then, while there are at least
#' three field rows per column, the output's curvature in the parameters
#' (covariances with the squares and products of the `tf` draws): a
#' parameter's error moves heating and cooling months differently, and a
#' linear correction alone leaves a step at the switch between them. The candidate's `share` is the
#' fraction of the remaining residual variance it explains (a partial R^2),
#' its mean over the posterior draws. Its interval says how much the share
#' rests on particular periods: leaving out blocks of about `n^(1/3)`
#' consecutive periods in turn, at most 100 blocks (delete-a-block
#' jackknife; the block keeps autocorrelated neighbours together), `share
#' -/+ z se`. The posterior
#' draws alone give no interval: their residuals differ only in what
#' recalibration absorbs, which the share leaves out. A candidate
#' that only mimics a parameter's effect gets a share near zero: the data
#' cannot tell it from parameter error.
#'
#' Chance is accounted for by a null that keeps the model's structure: the
#' partial R^2 of the posterior mean residual is compared with its
#' distribution over `n_null` residuals simulated from the fitted model
#' without any hidden effect, `N(0, C)` with `C` the emulator's uncertainty
#' at the field rows given the runs plus the observation noise (averaged
#' over draws), projected like the data; with the basis emulator (the
#' default above 36 field rows) each null residual comes from one draw in
#' turn (its components' uncertainty, truncated rest and white or AR(1)
#' noise), at a cost linear in the rows. The emulator's part is inflated by
#' how much the emulator understates its own error when each simulation
#' run is predicted from the others (leave one run out; with the basis
#' emulator, 10-fold cross-validation over the runs with each component
#' fitted again, as leave-one-out with its fitted length scales held cannot
#' tell they are too long), so an overconfident emulator does not raise
#' alarms. Unlike shuffling the candidate,
#' this keeps the smoothness along the inputs that the emulator's error has.
#' Each candidate's partial R^2 is put on one scale as a normal score
#' under its null (`z`, through the Beta distribution with the null's mean
#' and variance, so that terms of one and two columns compare), and the
#' p-values are adjusted for all candidates at once by the max-statistic
#' method of Westfall and Young: a candidate's adjusted p-value is the share
#' of null residuals in which some candidate reaches its `z`. With regions,
#' the main candidates and the regions are adjusted as two families that
#' share `alpha` (weighted Bonferroni: 80 % to the candidates, 20 % to the
#' regions, whose p-values are divided by those shares), so a region must be
#' clearly beyond chance to be named: the null misses part of the
#' emulator's error at a regime switch (heating to cooling), which is
#' step-shaped. A candidate `explains` the discrepancy when its adjusted
#' p-value is below `alpha` and it also predicts rows left out: `cv_gain`,
#' the fraction by which adding it to the recalibration directions reduces
#' the leave-one-out error of the posterior mean residual, is positive (a
#' term that fits a few rows or the noise makes that error larger). The
#' cut of a region or hinge beyond chance is first moved to where the data
#' put the effect's edge: the candidate cuts are a coarse grid (few terms
#' keep the test's power), so among the splits between consecutive field
#' values of the input around the tested cut (up to half-way to the next
#' candidate cuts), the one whose term explains the most of the posterior
#' mean residual is named; its `share` and `cv_gain` are the refined
#' term's (a grid cut with rows on the wrong side of the edge predicts
#' them badly), `z` and `p_value` the tested cut's. The cross-validation
#' only removes names: false alarms are held by the p-values alone. A line
#' holds its region's step and nearly holds its candidate over all rows, so
#' by share it would always win: a named line keeps its name only when it
#' explains more than each of the two beyond chance (against the null
#' residuals, the largest over the lines it was chosen among, at `alpha`)
#' and predicts left-out rows better than it, and is otherwise named as the
#' simpler of the two that explains more. The verdict names the
#' explaining candidate with the largest share, or says that none explains
#' it: for a correct simulator, that happens in about
#' `1 - alpha` of data sets (measured in `bench/bench-false-alarms.R` and
#' `bench/bench-diagnosis.R`). When another explaining candidate, a
#' different cause, explains the same part of the residual (the two
#' together less than 10 % more than the first alone) and explains as much
#' as the first in at least 10 % of the posterior draws, the verdict says
#' the data cannot tell them apart and names both.

#' On a fit on several outputs each output's discrepancy is explained on
#' its own (its residual, its candidates, its null), each at `alpha`: over
#' `K` outputs the chance of a false alarm in any is at most `K * alpha`
#' (give `alpha / K` to hold `alpha` for the fit).
#'
#' @param fit A `bayesbem_fit`.
#' @param covariates Optional data frame with one row per field row (in the
#'   field data's order) of further candidates; on several outputs, a list
#'   of such tables named by output.
#' @param level Probability of the shares' intervals (a delete-a-block
#'   jackknife over periods: how much each share rests on particular periods).
#' @param alpha Family-wise error rate of the "explains" decisions.
#' @param n_null Number of simulated null residuals: at least 100 with
#'   regions, 20 without, at `alpha = 0.05` (an error says so), since no
#'   adjusted p-value can be smaller than `1 / (n_null + 1)` divided by the
#'   family's share of `alpha`.
#' @template args-ndraws
#' @param regions Also try steps in each input and each candidate's effect
#'   in part of another input's range (see Details); [extend()] takes the
#'   names it gives. With regions, false alarms stay near `alpha`
#'   (`bench/results/diagnosis.md`) and an
#'   effect acting only in warm months is named with its region, which the
#'   candidates alone miss ("False alarms and detection"). `FALSE` scores
#'   the candidates alone (faster: a few terms instead of hundreds).
#' @param seed Random seed of the null residuals.
#' @return A data frame of class `bayesbem_explanation`, the explaining candidates
#'   first, each group by `share`: `candidate`, `share`, `lower`, `upper`
#'   (fractions), `z`, `p_value` (adjusted), `cv_gain`, `explains`; the
#'   verdict is in `attr(, "verdict")`, and the candidates the first cannot
#'   be told apart from in `attr(, "ambiguous")`. Printing shows every candidate and the regions
#'   named or ranked next. On several outputs, a `bayesbem_explanations`:
#'   `outputs`, each output's explanation by output; its `summary()` stacks
#'   their tables with a first column `output`.
#' @family discrepancy
#' @export
#' @examples
#' working <- data.frame(working_days = c(22, 20, 21, 22, 22, 20, 23, 21, 21, 23, 20, 21))
#' explain_discrepancy(seb_fit, working, ndraws = 100, n_null = 200, seed = 1)
explain_discrepancy <- function(fit, covariates = NULL, level = 0.9, alpha = 0.05,
                                n_null = 1000, ndraws = NULL, regions = TRUE, seed = NULL) {
  check_fit(fit)
  check_count(n_null)
  check_probability(level)
  check_probability(alpha)
  check_bool(regions)
  UseMethod("explain_discrepancy")
}

#' @export
explain_discrepancy.bayesbem_fit <- function(fit, covariates = NULL, level = 0.9, alpha = 0.05,
                                             n_null = 1000, ndraws = NULL, regions = TRUE,
                                             seed = NULL) {
  weights <- if (regions) region_weights else c(main = 1)
  check_null_size(n_null, alpha, weights)
  data <- fit$data
  candidates <- explanation_candidates(data, covariates)
  main <- main_terms(candidates)
  terms <- c(main, if (regions) region_terms(candidates, data$field[data$names$x]))
  family <- rep(c("main", "region"), c(length(main), length(terms) - length(main)))
  rg <- recalibration_geometry(fit, ndraws)
  residual <- rg$given_runs$residual
  basis <- rg$basis
  nuisance <- qr(basis)
  inflation <- emulator_inflation(rg$g, rg$pars)
  null <- with_seed(seed, null_residuals(rg$g, rg$pars, rg$given_runs, inflation, n_null))
  mean_residual <- colMeans(residual)
  blocks <- jackknife_blocks(basis, mean_residual)
  free_draws <- with_totals(qr.resid(nuisance, t(residual)))
  free <- qr.resid(nuisance, mean_residual)
  null_free <- with_totals(qr.resid(nuisance, null))
  scores <- lapply(terms, function(b) {
    term_scores(b, free_draws, free, null_free, nuisance, level, blocks)
  })
  out <- data.frame(candidate = names(terms),
                    do.call(rbind, lapply(scores, `[[`, "summary")), row.names = NULL)
  # a line is tested and cross-validated as itself and as its slope alone
  # (a slope through zero, one column), each a term of the family
  lines <- which(vapply(names(terms), is_line, logical(1)))
  slopes <- lapply(terms[lines], function(b) {
    chance <- chance_z(b[, 2], free, null_free, nuisance)
    list(summary = data.frame(z = chance$z), null_z = chance$null_z)
  })
  p <- adjusted_p_values(c(scores, slopes), c(family, rep("region", length(lines))), weights)
  out$p_value <- p[seq_along(terms)]
  out$p_value[lines] <- pmin(out$p_value[lines], p[-seq_along(terms)])
  out$z[lines] <- pmax(out$z[lines], vapply(slopes, function(s) s$summary$z, numeric(1)))
  baseline <- press(basis, mean_residual)
  out$cv_gain <- vapply(names(terms), function(l) {
    cv_gain(mean_residual, basis, terms[[l]], baseline, is_line(l), nuisance)
  }, numeric(1), USE.NAMES = FALSE)
  out$explains <- out$p_value < alpha & out$cv_gain > 0
  # regions beyond chance get the cut the data put the edge at, and a line
  # that beats no simpler term beyond chance is named as that term; the
  # test stands (p_value and z are the grid term's), the rest is the named
  # term's, its cross-validation too: a grid cut that leaves the edge's
  # rows on the wrong side predicts them worse than the effect does
  region_labels <- names(terms)[family == "region"]
  memo <- new.env()
  for (i in which(out$p_value < alpha & family == "region")) {
    label <- simplest_region(refine_region(out$candidate[i], candidates, free, nuisance),
                             candidates, basis, mean_residual, null_free, alpha, main,
                             region_labels, memo)
    if (label == out$candidate[i]) next
    terms[[i]] <- if (label %in% names(main)) main[[label]] else term_matrix(label, candidates)
    names(terms)[i] <- out$candidate[i] <- label
    scores[[i]] <- term_scores(terms[[i]], free_draws, free, null_free, nuisance, level, blocks)
    out[i, c("share", "lower", "upper")] <- scores[[i]]$summary[c("share", "lower", "upper")]
    out$cv_gain[i] <- cv_gain(mean_residual, basis, terms[[i]], baseline, is_line(label), nuisance)
    out$explains[i] <- out$cv_gain[i] > 0
  }
  out <- out[order(!out$explains, -out$share), ]
  # a line named as a simpler term can repeat that term
  out <- out[!duplicated(out$candidate), ]
  rownames(out) <- NULL
  shares <- stats::setNames(lapply(scores, `[[`, "shares"), names(terms))
  ambiguous <- ambiguous_with(out, terms, shares, free, nuisance)
  structure(out, class = c("bayesbem_explanation", "data.frame"), level = level, alpha = alpha,
            ambiguous = ambiguous, verdict = explanation_verdict(out, level, ambiguous))
}

# The explaining candidates of another cause that the data cannot tell
# from the first: together with it they explain less than 10 % more than
# it alone (R^2 of the posterior mean residual beyond recalibration: the
# same part of the residual), and they explain as much as it (to
# rounding) in at least 10 % of the posterior draws (`shares`, per term
# and draw). Terms are of one cause when one's variables include the
# other's ("rh > 47" and "solar, where rh > 47"; "temp > 15" and "rh,
# where temp > 15"): a shape of the same effect, not another explanation.
ambiguous_with <- function(x, terms, shares, free, nuisance) {
  named <- x$candidate[x$explains]
  if (length(named) < 2L) {
    return(character(0))
  }
  r2 <- function(names) partial_r_squared(do.call(cbind, unname(terms[names])), free, nuisance)
  nested <- function(a, b) {
    all(term_variables(a) %in% term_variables(b)) || all(term_variables(b) %in% term_variables(a))
  }
  top <- r2(named[1])
  others <- named[-1][!vapply(named[-1], nested, logical(1), b = named[1])]
  close <- vapply(others, function(o) {
    r2(c(named[1], o)) < 1.1 * top && mean(shares[[o]] >= shares[[named[1]]] - 1e-8) >= 0.1
  }, logical(1))
  others <- others[close]
  others[!duplicated(vapply(others, function(o) paste(sort(term_variables(o)), collapse = ","), ""))]
}

explanation_verdict <- function(x, level, ambiguous = character(0)) {
  cause <- x[x$explains, , drop = FALSE]
  if (nrow(cause) == 0L) {
    return("No candidate explains the discrepancy beyond chance.")
  }
  top <- cause[1, ]
  if (length(ambiguous) > 0L) {
    return(sprintf("The discrepancy is explained beyond chance, but ambiguously between %s: each explains about %.0f%% of the simulator residual, and together hardly more. The data cannot tell them apart; a measurement or knowledge of the building can.",
                   and_list(c(top$candidate, ambiguous)), 100 * top$share))
  }
  # a candidate named in several regions is named once, and at most five
  # others (at a year of hours dozens of terms can be beyond chance)
  others <- unique(sub(", where .*$", "", cause$candidate))[-1]
  others <- if (length(others) > 0L) {
    more <- if (length(others) > 5L) sprintf(" and %d more in the table", length(others) - 5L)
    sprintf(" (also beyond chance: %s%s)", paste(utils::head(others, 5L), collapse = ", "),
            more %||% "")
  } else {
    ""
  }
  sprintf("The discrepancy is best explained by %s: %.0f%% of the simulator residual (%g%% interval over left-out periods %.0f-%.0f%%, adjusted p = %.2g)%s.",
          top$candidate, 100 * top$share, 100 * level, 100 * top$lower, 100 * top$upper,
          top$p_value, others)
}

#' @export
print.bayesbem_explanation <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(attr(x, "verdict"), "\n\n")
  # every candidate, and of the regions those named and the next three
  region <- grepl(", where | [<>] |^max\\(", x$candidate)
  shown <- !region | x$explains | cumsum(region & !x$explains) <= 3 & region
  print_rounded(as.data.frame(unclass(x))[shown, ], digits)
  if (any(!shown)) cat(sprintf("(%d more regions, none beyond chance)\n", sum(!shown)))
  invisible(x)
}

# Each output's explanation, its terms `covariates[[k]]`.
#' @export
explain_discrepancy.bayesbem_fit_outputs <- function(fit, covariates = NULL, level = 0.9,
                                                     alpha = 0.05, n_null = 1000, ndraws = NULL,
                                                     regions = TRUE, seed = NULL) {
  check_output_covariates(covariates, names(fit$outputs))
  outputs <- names(fit$outputs)
  each <- lapply(stats::setNames(outputs, outputs), function(k) {
    explain_discrepancy(fit$outputs[[k]], covariates[[k]], level = level, alpha = alpha,
                        n_null = n_null, ndraws = ndraws, regions = regions, seed = seed)
  })
  structure(list(outputs = each, alpha = alpha), class = "bayesbem_explanations")
}

#' @export
summary.bayesbem_explanations <- function(object, ...) {
  rlang::check_dots_empty()
  stack_outputs(lapply(object$outputs, function(e) as.data.frame(unclass(e))))
}

#' @export
print.bayesbem_explanations <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  for (k in names(x$outputs)) {
    cat_lines("{.strong {k}}")
    print(x$outputs[[k]], digits = digits)
    cat("\n")
  }
  invisible(x)
}
