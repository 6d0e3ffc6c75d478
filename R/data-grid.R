# Grid designs: every simulation run made at the field inputs (x_c = x_f),
# as in the paper's workflow. Then Sigma_eta is the Kronecker product of a
# run correlation and a field-input correlation, which koh.stan's grid
# likelihood and the grid prediction code exploit (inst/notes/decisions/S6-grid-designs.md).

# The grid layout of scaled field inputs `xf`, simulation inputs `xc` and
# design `tc`, or NULL when they do not form a full grid. The grid inputs are
# the distinct field inputs (field rows sharing their inputs, two calm night
# hours, share one) followed by any further simulation inputs (e.g. of
# held-out periods); every run (distinct row of tc) must have exactly one
# row at each grid input, in any order. A simulation row is at a field input
# when every scaled input is within `tol` of it (tables written separately
# differ by rounding). Returns the grid inputs `x` (the `n` field inputs
# first), `field` (the grid input of each field row), `index[i, a]` (the
# simulation row of run a at grid input i), the run `design`, each
# simulation row's grid input `period`, and `max_diff`, the largest
# difference matched.
grid_layout <- function(xf, xc, tc, tol = 0) {
  field <- row_groups(xf)
  xf <- xf[!duplicated(field), , drop = FALSE]
  if (has_near_rows(xf, tol)) {
    return(NULL)
  }
  n <- nrow(xf)
  near <- nearest_rows(xc, xf)
  nearest <- near$index
  gap <- near$gap
  matched <- gap <= tol
  extra_key <- row_keys(xc[!matched, , drop = FALSE])
  period <- nearest
  period[!matched] <- n + match(extra_key, unique(extra_key))
  x <- rbind(xf, xc[!matched, , drop = FALSE][!duplicated(extra_key), , drop = FALSE])
  run <- row_groups(tc)
  mt <- max(run)
  if (mt < 2L || length(period) != nrow(x) * mt || anyDuplicated(cbind(period, run)) > 0L) {
    return(NULL)
  }
  index <- matrix(NA_integer_, nrow(x), mt)
  index[cbind(period, run)] <- seq_along(period)
  list(n = n, n_x = nrow(x), mt = mt, x = x, field = field, index = index,
       design = tc[index[1, ], , drop = FALSE], period = period,
       max_diff = max(c(0, gap[matched])))
}

# The largest absolute difference over the columns of every row of `a`
# with every row of `b`.
max_abs_dist <- function(a, b) {
  Reduce(pmax, lapply(seq_len(ncol(a)), function(k) abs(outer(a[, k], b[, k], "-"))))
}

# Whether two rows of `x` lie within `tol` of each other in every column:
# along the first column sorted, each row against those within `tol` there
# (never all pairs: a year of hours is 8,760 rows).
has_near_rows <- function(x, tol) {
  s <- x[order(x[, 1]), , drop = FALSE]
  upper <- findInterval(s[, 1] + tol, s[, 1])
  for (i in which(upper > seq_len(nrow(s)))) {
    if (any(max_abs_dist(s[i, , drop = FALSE], s[(i + 1L):upper[i], , drop = FALSE]) <= tol)) {
      return(TRUE)
    }
  }
  FALSE
}

# The nearest row of `xf` to each row of `xc` (`index`, the first of equals)
# and its largest absolute difference (`gap`): identical rows by their
# keys, the others in chunks of about 1e7 pairs, so that memory stays
# bounded (runs of a year of hours against its field hours are 2e9 pairs).
nearest_rows <- function(xc, xf) {
  index <- match(row_keys(xc), row_keys(xf))
  gap <- numeric(nrow(xc))
  rest <- which(is.na(index))
  size <- max(1L, floor(1e7 / nrow(xf)))
  for (chunk in split(rest, ceiling(seq_along(rest) / size))) {
    d <- max_abs_dist(xc[chunk, , drop = FALSE], xf)
    index[chunk] <- max.col(-d, ties.method = "first")
    gap[chunk] <- d[cbind(seq_along(chunk), index[chunk])]
  }
  list(index = index, gap = gap)
}

# The grid layout within `tol`; by default within rounding and, failing
# that, within 5 % of each input's range, said in a message (koh_data()'s
# `grid_tol`).
find_grid <- function(xf, xc, tc, tol, x_names) {
  if (!is.null(tol)) {
    check_number(tol, "argument", arg = "grid_tol")
    return(grid_layout(xf, xc, tc, tol))
  }
  grid <- grid_layout(xf, xc, tc, 1e-6)
  if (!is.null(grid)) {
    return(grid)
  }
  grid <- grid_layout(xf, xc, tc, 0.05)
  if (!is.null(grid)) {
    gap <- apply(abs(xc - grid$x[grid$period, , drop = FALSE]), 2, max)
    differ <- x_names[gap > 1e-6]
    cli::cli_inform(c(i = "The runs' inputs match the field inputs within {signif(100 * grid$max_diff, 2)}% of their range, not exactly ({.field {differ}}): taken as the field's.",
                      " " = "So the fit uses the grid likelihood. Give {.code grid_tol = 0} to keep them apart (the dense likelihood, far slower)."),
                    class = "bayesbem_message_near_grid")
  }
  grid
}

# The scaled simulation outputs of a grid design as a matrix: run a at grid
# input i in element (i, a).
grid_runs <- function(data) {
  matrix(data$eta[data$grid$index], data$grid$n_x)
}

# The grid input of each field row: periods sharing their inputs share
# one (grids made before `field` was kept have one per field row).
field_rows <- function(grid) {
  grid$field %||% seq_len(grid$n)
}

# The grid inputs of the field rows (scaled), and the runs there (field
# row by run).
field_grid_inputs <- function(data) {
  data$grid$x[field_rows(data$grid), , drop = FALSE]
}

field_runs <- function(data) {
  grid_runs(data)[field_rows(data$grid), , drop = FALSE]
}

# Keys of a table's rows to 6 significant digits: the periods of a simulator
# and of a fit match by value, whatever rounding their inputs went through.
value_keys <- function(x) row_keys(signif(as.matrix(x), 6))

# Each element's occurrence among the equal ones before it: 1, 2, ...
nth_occurrence <- function(v) {
  stats::ave(seq_along(v), v, FUN = seq_along)
}

# match() that pairs repeated keys in order: the k-th element of `x` with a
# key takes the k-th row of `table` with it (periods sharing their inputs).
match_in_order <- function(x, table) {
  match(paste(x, nth_occurrence(x)), paste(table, nth_occurrence(table)))
}

# Exact keys of matrix rows (hexadecimal doubles), so that rows match only
# when every value is identical, as Stan's equal_rows() requires.
row_keys <- function(x) {
  x <- as.matrix(x)
  if (nrow(x) == 0L) {
    return(character(0))
  }
  do.call(paste, lapply(seq_len(ncol(x)), function(k) sprintf("%a", x[, k])))
}

# The group of each matrix row, numbered in order of first appearance: rows
# with identical values share one (the runs of a design `tc`).
row_groups <- function(x) {
  key <- row_keys(x)
  match(key, unique(key))
}

# The one test of a resolved likelihood structure (choose_structure()):
# TRUE for "grid", given the string or what holds it as `$structure` (a
# calibration spec, a fit's settings, a geometry).
is_grid <- function(x) identical(if (is.list(x)) x$structure else x, "grid")

# Which likelihood to use: "grid" when the design is a grid and nothing
# rules it out, else "dense"; `structure` forces either.
choose_structure <- function(data, structure, predict_at = NULL, call = rlang::caller_env()) {
  if (structure == "dense") {
    return("dense")
  }
  grid_ok <- !is.null(data$grid) && is.null(predict_at)
  if (structure == "grid" && !grid_ok) {
    reason <- if (is.null(data$grid)) {
      c(x = "The simulation table is not a full grid over the field inputs.",
        i = "A grid has every run at every field input (and at any further inputs), and distinct field inputs.")
    } else {
      c(x = "{.arg predict_at} needs the dense program.",
        i = "Predict after the fit with {.fn predict} instead.")
    }
    abort_bayesbem(c("{.code structure = \"grid\"} cannot be used.", reason),
                   "argument", call = call)
  }
  if (grid_ok) "grid" else "dense"
}

# The measured total of the field rows and every run's total over the same
# rows, in output units. A measured total outside the runs' totals is one
# that no setting the runs span reaches: the prior predictive misses the
# meter, and the discrepancy would carry the whole gap.
prior_totals <- function(data) {
  runs <- unscale_y(field_runs(data), data$scaling)
  list(measured = sum(unscale_y(data$y, data$scaling)), runs = colSums(runs))
}
