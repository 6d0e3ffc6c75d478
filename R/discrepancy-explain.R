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
#' where the input passes it ("rh > 47"), and each other candidate's effect
#' only on one side of it ("solar, where temp < 4.9").

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
#' summarised over draws by its mean and a central interval. A candidate
#' that only mimics a parameter's effect gets a share near zero: the data
#' cannot tell it from parameter error.
#'
#' Chance is accounted for by a null that keeps the model's structure: the
#' partial R^2 of the posterior mean residual is compared with its
#' distribution over `n_null` residuals simulated from the fitted model
#' without any hidden effect, `N(0, C)` with `C` the emulator's uncertainty
#' at the field rows given the runs plus the observation noise (averaged
#' over draws), projected like the data. The emulator's part is inflated by
#' how much the emulator understates its own error when each simulation
#' run is predicted from the others (leave one run out), so an
#' overconfident emulator does not raise alarms. Unlike shuffling the candidate,
#' this keeps the smoothness along the inputs that the emulator's error has.
#' Each candidate's excess over its null is standardised (`z`), and the
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
#' cut of a named region is then moved to where the data put the effect's
#' edge: the candidate cuts are a coarse grid (few terms keep the test's
#' power), so among the splits between consecutive field values of the
#' input around the tested cut (up to half-way to the next candidate cuts),
#' the one whose term explains the most of the posterior mean residual is
#' named; its `share` and `cv_gain` are the refined term's, `z` and
#' `p_value` the tested cut's. The
#' verdict names the explaining candidate with the largest share, or says
#' that none explains it: for a correct simulator, that happens in about
#' `1 - alpha` of data sets (measured in `bench/bench-false-alarms.R` and
#' `bench/bench-diagnosis.R`). When another explaining candidate, a
#' different cause, explains the same part of the residual (the two
#' together less than 10 % more than the first alone) and explains as much
#' as the first in at least 10 % of the posterior draws, the verdict says
#' the data cannot tell them apart and names both.

#' @param fit A `bayesbem_fit`.
#' @param covariates Optional data frame with one row per field row (in the
#'   field data's order) of further candidates.
#' @template args-level
#' @param alpha Family-wise error rate of the "explains" decisions.
#' @param n_null Number of simulated null residuals: at least 100 with
#'   regions, 20 without, at `alpha = 0.05` (an error says so), since no
#'   adjusted p-value can be smaller than `1 / (n_null + 1)` divided by the
#'   family's share of `alpha`.
#' @template args-ndraws
#' @param regions Also try steps in each input and each candidate's effect
#'   in part of another input's range (see Details); [extend()] takes the
#'   names it gives. With regions, false alarms stay near `alpha`
#'   (`bench/RESULTS.md`, "Diagnosis on problems not tuned on") and an
#'   effect acting only in warm months is named with its region, which the
#'   candidates alone miss ("False alarms and detection"). `FALSE` scores
#'   the candidates alone (faster: a few terms instead of hundreds).
#' @param seed Random seed of the null residuals.
#' @return A data frame of class `bayesbem_explanation`, the explaining candidates
#'   first, each group by `share`: `candidate`, `share`, `lower`, `upper`
#'   (fractions), `z`, `p_value` (adjusted), `cv_gain`, `explains`; the
#'   verdict is in `attr(, "verdict")`, and the candidates the first cannot
#'   be told apart from in `attr(, "ambiguous")`. Printing shows every candidate and the regions
#'   named or ranked next.
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
  weights <- if (regions) region_weights else c(main = 1)
  check_null_size(n_null, alpha, weights)
  data <- fit$data
  candidates <- explanation_candidates(data, covariates)
  main <- main_terms(candidates)
  terms <- c(main, if (regions) region_terms(candidates, data$field[data$names$x]))
  family <- rep(c("main", "region"), c(length(main), length(terms) - length(main)))
  g <- gp_geometry(data, NULL, fit_structure(fit))
  pars <- draw_parameters(fit, ndraws)
  given_runs <- lapply(pars, function(par) residual_given_runs(g, par))
  residual <- do.call(rbind, lapply(given_runs, `[[`, "residual"))
  tf <- do.call(rbind, lapply(pars, `[[`, "tf"))
  basis <- recalibration_basis(-residual, tf)
  nuisance <- qr(basis)
  mean_of <- function(part) Reduce(`+`, lapply(given_runs, `[[`, part)) / length(given_runs)
  inflation <- emulator_inflation(g, pars)
  null_cov <- inflation * mean_of("emulator") + diag(mean_of("noise"), data$n)
  n <- data$n
  null <- with_seed(seed, crossprod(jittered_chol(null_cov), matrix(stats::rnorm(n * n_null), n)))
  scores <- lapply(terms, function(b) term_scores(b, residual, nuisance, null, level))
  out <- data.frame(candidate = names(terms),
                    do.call(rbind, lapply(scores, `[[`, "summary")), row.names = NULL)
  out$p_value <- adjusted_p_values(scores, family, weights)
  mean_residual <- colMeans(residual)
  baseline <- press(basis, mean_residual)
  out$cv_gain <- vapply(terms, function(b) cv_gain(mean_residual, basis, b, baseline), numeric(1))
  out$explains <- out$p_value < alpha & out$cv_gain > 0
  # named regions get the cut the data put the edge at; the test stands
  # (p_value and z are the grid cut's), the rest is the refined term's
  free <- qr.resid(nuisance, mean_residual)
  for (i in which(out$explains & family == "region")) {
    label <- refine_region(out$candidate[i], candidates, free, nuisance)
    if (label == out$candidate[i]) next
    terms[[i]] <- cbind(region_values(label, candidates))
    names(terms)[i] <- out$candidate[i] <- label
    scores[[i]] <- term_scores(terms[[i]], residual, nuisance, null, level)
    out[i, c("share", "lower", "upper")] <- scores[[i]]$summary[c("share", "lower", "upper")]
    out$cv_gain[i] <- cv_gain(mean_residual, basis, terms[[i]], baseline)
    out$explains[i] <- out$cv_gain[i] > 0
  }
  out <- out[order(!out$explains, -out$share), ]
  rownames(out) <- NULL
  shares <- stats::setNames(lapply(scores, `[[`, "shares"), names(terms))
  ambiguous <- ambiguous_with(out, terms, shares, free, nuisance)
  structure(out, class = c("bayesbem_explanation", "data.frame"), level = level, alpha = alpha,
            ambiguous = ambiguous, verdict = explanation_verdict(out, level, ambiguous))
}

# How much better the posterior mean residual is predicted out of sample
# with the term than by recalibration alone: 1 - PRESS(basis, b) /
# PRESS(basis), PRESS the sum of squared leave-one-out errors of the least
# squares fit, e_i / (1 - h_ii). Positive when the term predicts left-out
# rows (a term that only fits noise, or a few rows, makes PRESS larger).
cv_gain <- function(r, basis, b, baseline = press(basis, r)) {
  1 - press(cbind(basis, b), r) / baseline
}

# Sum of squared leave-one-out errors of the least squares fit of r on the
# columns of x; Inf when a row is fitted exactly (leverage 1).
press <- function(x, r) {
  q <- qr(x)
  h <- rowSums(qr.Q(q)[, seq_len(q$rank), drop = FALSE]^2)
  if (any(h > 1 - 1e-8)) return(Inf)
  sum((qr.resid(q, r) / (1 - h))^2)
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
  r2 <- function(names) free_r_squared(do.call(cbind, unname(terms[names])), free, nuisance)
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

# The share of alpha each family of terms gets when regions are tried: the
# main terms keep most of it; the many region terms, whose null is the
# less certain (the emulator's error at a regime switch is step-shaped and
# not in it), a fifth (chosen by measurement, bench/RESULTS.md).
region_weights <- c(main = 0.8, region = 0.2)

# Adjusted p-values: within each family of terms, the max-statistic
# adjustment of Westfall and Young (a term's standardised R^2 `z` against
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

# One basis per candidate: linear and quadratic terms (standardised), or a
# linear term for a two-valued candidate such as a step at a date.
main_terms <- function(candidates) {
  lapply(candidates, function(v) {
    u <- (v - mean(v)) / stats::sd(v)
    if (length(unique(u)) > 2L) cbind(u, u^2) else cbind(u)
  })
}

# Effects that act in part of an input's range, at the thresholds `c` of
# each observable input `b` (region_cuts()): a step where b passes c, "b >
# c", and for each other candidate `a`, its effect only on one side, "a,
# where b < c" (a there, 0 elsewhere: not centred, so a gain that only acts
# there, such as solar gains in cold months, is one term). Each term is
# computed from its name by region_values(), in the units of `a`, so that
# extend() and predict() rebuild it from the name alone.
region_terms <- function(candidates, inputs) {
  labels <- unlist(lapply(names(inputs), function(b) {
    lapply(region_cuts(inputs[[b]]), function(cut) {
      others <- setdiff(names(candidates), b)
      c(region_label("", b, ">", cut),
        region_label(rep(others, 2), b, rep(c("<", ">"), each = length(others)), cut))
    })
  }))
  stats::setNames(lapply(labels, function(l) cbind(region_values(l, candidates))), labels)
}

# The thresholds of one input: at each quartile, tertile and median, the
# shortest decimal that splits the values as the quantile does (so that a
# region's name defines it exactly), with at least 5 rows on each side.
region_cuts <- function(x) {
  values <- sort(unique(x))
  if (length(values) < 3L) {
    return(numeric(0))
  }
  cuts <- vapply(stats::quantile(x, c(1, 1.5, 2, 2.5, 3) / 4, names = FALSE), function(q) {
    short_cut(max(values[values <= q]), min(values[values > q], Inf))
  }, numeric(1))
  supported_cuts(x, unique(cuts))
}

# The shortest decimal c with lower <= c < upper (NA when upper is Inf or
# none of 15 digits splits the two).
short_cut <- function(lower, upper) {
  short <- signif((lower + upper) / 2, seq_len(15))
  short[short >= lower & short < upper][1]
}

# The finite cuts with at least 5 rows on each side.
supported_cuts <- function(x, cuts) {
  cuts <- cuts[is.finite(cuts)]
  cuts[vapply(cuts, function(cut) min(sum(x > cut), sum(x <= cut)) >= 5L, logical(1))]
}

# A region's name: "b > c" for a step (effect ""), "a, where b < c".
region_label <- function(effect, input, side, cut) {
  label <- vapply(cut, format, character(1), digits = 15)
  where <- sprintf("%s, where %s %s %s", effect, input, side, label)
  ifelse(rep_len(nzchar(effect), length(where)), where, sprintf("%s %s %s", input, side, label))
}

# A named region with its cut moved to where the data put the edge: the
# candidate cuts are a coarse grid (few terms keep the test's power), and
# an effect's edge usually lies between them, so that the grid's cut
# leaves some rows on the wrong side. Among the splits between consecutive
# values of the input (short_cut()) from half-way to the grid's lower
# neighbour to half-way to its upper one (so no two grid cuts refine to
# the same), the one whose term explains the most of the residual beyond
# recalibration (`free`, made orthogonal to `nuisance`).
refine_region <- function(name, candidates, free, nuisance) {
  parts <- parse_region(name)
  x <- candidates[[parts$input]]
  grid <- region_cuts(x)
  below <- max(c(-Inf, grid[grid < parts$cut]))
  above <- min(c(Inf, grid[grid > parts$cut]))
  values <- sort(unique(x))
  cuts <- mapply(short_cut, values[-length(values)], values[-1])
  cuts <- supported_cuts(x, cuts[cuts > (below + parts$cut) / 2 & cuts <= (parts$cut + above) / 2])
  if (length(cuts) < 2L) {
    return(name)
  }
  labels <- region_label(parts$effect, parts$input, parts$side, cuts)
  explained <- vapply(labels, function(l) free_r_squared(region_values(l, candidates), free, nuisance),
                      numeric(1))
  labels[which.max(explained)]
}

# R^2 of the posterior mean residual beyond recalibration (`free`, already
# orthogonal to `nuisance`) by the columns of `b`, made orthogonal too.
free_r_squared <- function(b, free, nuisance) {
  b <- qr.resid(nuisance, cbind(b))
  sum(qr.fitted(qr(b), free)^2) / sum(free^2)
}

# The values of a region term named as explain_discrepancy() prints it ("a,
# where b < c", "b > c") or as a covariate column ("a:b<c", "b>c"), from the
# columns of `table`: a where b <= c (or b > c), 0 elsewhere; a step is 1
# where b > c. NULL when `name` is no such name or names columns `table`
# lacks.
region_values <- function(name, table) {
  parts <- parse_region(name)
  if (is.null(parts) || !all(setdiff(c(parts$effect, parts$input), "") %in% names(table))) {
    return(NULL)
  }
  inside <- if (parts$side == ">") table[[parts$input]] > parts$cut else table[[parts$input]] <= parts$cut
  if (nzchar(parts$effect)) table[[parts$effect]] * inside else as.numeric(inside)
}

# A region's name split into the candidate whose effect it restricts
# (`effect`, "" for a step), the `input` it is a region of, the `side`
# ("<" or ">") and the `cut`; NULL when `name` is no region.
parse_region <- function(name) {
  compact <- region_column_name(name)
  parts <- regmatches(compact, regexec("^(?:([^:]+):)?([^<>]+)([<>])(.+)$", compact))[[1]]
  cut <- suppressWarnings(as.numeric(parts[5]))
  if (length(parts) == 0L || is.na(cut)) {
    return(NULL)
  }
  list(effect = parts[2], input = parts[3], side = parts[4], cut = cut)
}

# The candidates a term is made of: a region's effect and input, or the
# candidate itself.
term_variables <- function(name) {
  parts <- parse_region(name)
  if (is.null(parts)) name else setdiff(c(parts$effect, parts$input), "")
}

# A region's name as a covariate column (and in `gamma[<name>]`): no commas
# or spaces, "occupancy, where temp > 14.9" -> "occupancy:temp>14.9".
region_column_name <- function(region) {
  gsub(" ", "", sub(", where ", ":", region, fixed = TRUE), fixed = TRUE)
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

# For one draw: the field outputs' residual from the emulator's mean given
# the runs (standardised, less any parametric discrepancy terms), and the
# parts of its covariance without a discrepancy: the emulator's uncertainty
# given the runs and the noise variance.
residual_given_runs <- function(g, par) {
  rg <- residual_geometry(g, par)
  fm <- field_given_runs(rg, par)
  noise <- 1 / par$lambda_e
  emulator <- fm$cov - delta_cov(g$ff, par)
  diag(emulator) <- diag(emulator) - noise
  list(residual = field_y(rg, par) - fm$mean, emulator = emulator, noise = noise)
}

# How much the emulator understates its own error: the mean squared
# standardised error of each simulation run predicted from the others
# (leave one run out, at all its inputs), over up to 20 draws; 1 for a
# calibrated emulator, never below 1. Grid designs use the Kronecker form
# (the run's column of E given the other columns); others the precision
# matrix of the runs (block of each run's rows).
emulator_inflation <- function(g, pars) {
  pars <- pars[draw_subset(length(pars), 20L)]
  kappa <- vapply(pars, function(par) {
    rg <- residual_geometry(g, par)
    dg <- draw_geometry(rg, par)
    kt <- jittered_cor(rg$tt, dg$bt, par$nugget)
    if (rg$structure == "grid") {
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
# (partial R^2 given the QR-decomposed `nuisance` basis): per draw (rows of
# `residual`), summarised by mean and interval; for the posterior mean
# residual against the simulated null residuals (columns of `null`), the
# standardised excess `z` = (R^2 - null mean) / null sd, and the null
# residuals' own standardised values (for the max-statistic adjustment).
term_scores <- function(b, residual, nuisance, null, level) {
  free_b <- qr.resid(nuisance, b)
  # a column inside the recalibration span is all rounding error: drop it
  free_b <- free_b[, sqrt(colSums(free_b^2)) > 1e-8 * sqrt(colSums(b^2)), drop = FALSE]
  r_squared <- function(r) {
    if (ncol(free_b) == 0L) {
      return(rep(0, NCOL(r)))
    }
    fitted <- qr.fitted(qr(free_b), r)
    colSums(as.matrix(fitted)^2) / colSums(as.matrix(r)^2)
  }
  free <- qr.resid(nuisance, t(residual))
  shares <- r_squared(free)
  reference <- r_squared(qr.resid(nuisance, null))
  spread <- max(stats::sd(reference), .Machine$double.eps)
  z <- (r_squared(rowMeans(free)) - mean(reference)) / spread
  interval <- stats::quantile(shares, c((1 - level) / 2, (1 + level) / 2), names = FALSE)
  list(summary = data.frame(share = mean(shares), lower = interval[1], upper = interval[2], z = z),
       null_z = (reference - mean(reference)) / spread, shares = shares)
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
  # a candidate named in several regions is named once
  base <- unique(sub(", where .*$", "", cause$candidate))
  others <- if (length(base) > 1L) {
    sprintf(" (also beyond chance: %s)", paste(base[-1], collapse = ", "))
  } else {
    ""
  }
  sprintf("The discrepancy is best explained by %s: %.0f%% of the simulator residual (%g%% interval %.0f-%.0f%%, adjusted p = %.2g)%s.",
          top$candidate, 100 * top$share, 100 * level, 100 * top$lower, 100 * top$upper,
          top$p_value, others)
}

#' @export
print.bayesbem_explanation <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(attr(x, "verdict"), "\n\n")
  # every candidate, and of the regions those named and the next three
  region <- grepl(", where | [<>] ", x$candidate)
  shown <- !region | x$explains | cumsum(region & !x$explains) <= 3 & region
  print_rounded(as.data.frame(unclass(x))[shown, ], digits)
  if (any(!shown)) cat(sprintf("(%d more regions, none beyond chance)\n", sum(!shown)))
  invisible(x)
}
