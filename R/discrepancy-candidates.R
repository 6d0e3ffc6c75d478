# The candidate causes explain_discrepancy() scores: the inputs and
# covariates, their regions (steps, hinges and region-specific lines at
# quantile cuts) and a named region's cut refined to the data's gap.

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
# c"; hinges, "max(b - c, 0)" and "max(c - b, 0)" (a load growing past a
# balance point); and for each other candidate `a`, a line only on one
# side, "a, where b < c" (offset and slope of a there, 0 elsewhere: a
# latent load that grows with humidity once the building cools, solar
# gains only in cold months). Each term is computed from its name by
# term_columns(), in the units of `a`, so that extend() and predict()
# rebuild it from the name alone.
region_terms <- function(candidates, inputs) {
  labels <- unlist(lapply(names(inputs), function(b) {
    lapply(region_cuts(inputs[[b]]), function(cut) {
      others <- setdiff(names(candidates), b)
      c(region_label("", b, ">", cut), hinge_label(b, c(">", "<"), cut),
        region_label(rep(others, 2), b, rep(c("<", ">"), each = length(others)), cut))
    })
  }))
  stats::setNames(lapply(labels, term_matrix, table = candidates), labels)
}

# A term's columns (term_columns()) as a matrix.
term_matrix <- function(name, table) do.call(cbind, unname(term_columns(name, table)))

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

# A named region or hinge with its cut moved to where the data put the
# edge: the candidate cuts are a coarse grid (few terms keep the test's
# power), and an effect's edge usually lies between them, so that the
# grid's cut leaves some rows on the wrong side. Among the splits between
# consecutive values of the input (short_cut()) from half-way to the
# grid's lower neighbour to half-way to its upper one (so no two grid cuts
# refine to the same), the one whose term explains the most of the
# residual beyond recalibration (`free`, made orthogonal to `nuisance`).
refine_region <- function(name, candidates, free, nuisance) {
  hinge <- parse_hinge(name)
  parts <- hinge %||% parse_region(name)
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
  labels <- if (is.null(hinge)) region_label(parts$effect, parts$input, parts$side, cuts) else
    hinge_label(parts$input, parts$side, cuts)
  explained <- vapply(labels, function(l) partial_r_squared(term_matrix(l, candidates), free, nuisance),
                      numeric(1))
  labels[which.max(explained)]
}

# A named region-specific line ("a, where b > c"), or the simpler term it
# does not beat: its region's step "b > c" (its cut refined on its own) or
# the candidate `a` over all rows (its `main` terms). A line holds its step
# and nearly holds `a` (two columns where `a` has one), so the share alone
# would prefer it. Against each simpler term, the line's columns are tested
# given it and recalibration (`basis`): the R^2 of the posterior mean
# residual by them against the null residuals', adjusted by the max
# statistic over the lines it was chosen among (every candidate's line in
# that region, against the step; every line of `a`, among `labels`,
# against `a`), at `alpha`; and they must predict left-out rows given it
# (cv_gain(), as any named term: a line that differs from its step in one
# row fits that row and predicts nothing). Of the simpler terms the line
# does not beat, the one that explains most is named. Other terms are
# returned as they are. `null_free`: the null residuals beyond
# recalibration, with_totals(); `memo`: an environment that keeps the
# lines' scores for the next call (chances_given()).
simplest_region <- function(name, candidates, basis, mean_residual, null_free, alpha, main,
                            labels, memo = new.env()) {
  if (!is_line(name)) {
    return(name)
  }
  parts <- parse_region(name)
  step <- region_label("", parts$input, ">", parts$cut)
  others <- setdiff(names(candidates), parts$input)
  of_effect <- labels[vapply(labels, function(l) identical(parse_region(l)$effect, parts$effect),
                             logical(1))]
  simpler <- list(
    list(label = step, columns = region_values(step, candidates),
         lines = region_label(rep(others, 2), parts$input, rep(c("<", ">"), each = length(others)),
                              parts$cut)),
    list(label = parts$effect, columns = main[[parts$effect]], lines = of_effect))
  beaten <- vapply(simpler, function(alt) {
    chances <- chances_given(alt, unique(c(name, alt$lines)), candidates, basis, mean_residual,
                             null_free, memo)
    null_max <- do.call(pmax, lapply(chances, `[[`, "null_z"))
    (1 + sum(null_max >= chances[[1]]$z)) / (length(null_max) + 1) < alpha &&
      cv_gain(mean_residual, cbind(basis, alt$columns), term_matrix(name, candidates)) > 0
  }, logical(1))
  if (all(beaten)) {
    return(name)
  }
  nuisance <- qr(basis)
  free <- qr.resid(nuisance, mean_residual)
  kept <- simpler[!beaten]
  explained <- vapply(kept, function(alt) partial_r_squared(alt$columns, free, nuisance), numeric(1))
  best <- kept[[which.max(explained)]]$label
  if (best == step) refine_region(step, candidates, free, nuisance) else best
}

# chance_z() of each of the region-specific `lines` given recalibration
# (`basis`) and the simpler term `alt` (its `label` and `columns`), as a
# list, kept in the environment `memo` for later calls: every line of a
# candidate is scored against that candidate for each region named in it.
# `null_free`: the null residuals beyond recalibration, with_totals(). They
# are not projected again: a line's columns are made orthogonal to `alt`
# too (partial_r_squared()), so its products with them are the same, and
# only each residual's total sum of squares loses its part along `alt`:
# one product with the null residuals instead of a projection of each.
chances_given <- function(alt, lines, candidates, basis, mean_residual, null_free, memo) {
  keys <- paste(alt$label, lines, sep = "\r")
  missing <- which(!vapply(keys, exists, logical(1), envir = memo, inherits = FALSE))
  if (length(missing) > 0L) {
    nuisance <- qr(cbind(basis, alt$columns))
    free <- qr.resid(nuisance, mean_residual)
    along <- crossprod(qr.Q(nuisance)[, seq_len(nuisance$rank), drop = FALSE], null_free)
    null_alt <- structure(null_free, total = attr(null_free, "total") - colSums(along^2))
    for (k in missing) {
      assign(keys[k], chance_z(term_matrix(lines[k], candidates), free, null_alt, nuisance),
             envir = memo)
    }
  }
  unname(mget(keys, envir = memo))
}
