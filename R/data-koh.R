#' Field and simulation data for a KOH calibration
#'
#' Combines measured (field) data and simulation runs in the layout of Chong
#' and Menberg (2018), checks them, and scales them as the method requires.
#'
#' The field table holds the measured output `y` and the `p` observable
#' inputs `x`. The simulation table holds the simulator output `eta`, the
#' same `p` inputs, and the `q` calibration parameters `t` of each run. By
#' default columns are taken by position (field: `y`, then `x`; simulation:
#' `eta`, then `x`, then `t`); name them with `y`, `eta`, `x` and `t` to pick
#' columns by name instead (`x` names must then be in both tables).
#'
#' Simulation rows must be distinct: repeated runs with the same inputs and
#' parameters make the emulator's covariance singular; average them first.
#'
#' Scaling (undone for every number shown to users):
#' * `y` and `eta` are standardised with the mean and standard deviation of
#'   `eta`;
#' * each `x` column is mapped to \[0, 1\] with its minimum and maximum over
#'   field and simulation rows together;
#' * each `t` column is mapped to \[0, 1\] with its minimum and maximum over
#'   the simulation design.
#'
#' @param field A data frame (or numeric matrix) of field data.
#' @param sim A data frame (or numeric matrix) of simulation runs.
#' @param y,eta Names of the output column in `field` and in `sim`.
#' @param x Names of the observable-input columns, present in both tables.
#' @param t Names of the calibration-parameter columns in `sim`.
#' @param grid_tol Tolerance, on the scaled \[0, 1\] input scale, within
#'   which a simulation row's inputs count as a field row's. When every run
#'   has one row at each field input within this tolerance, the design is a
#'   grid: the simulation inputs are then taken to be the field inputs
#'   exactly (tables written separately often differ in the last digits; the
#'   shipped ones by about 1e-8), `print()` reports the largest difference,
#'   and [calibrate()] can use the fast grid likelihood. Use `0` to require
#'   identical values.
#' @return An object of class `koh_data`: the scaled matrices `y`, `eta`,
#'   `xf`, `xc`, `tc`, the column names, the sizes `n`, `m`, `p`, `q`, the
#'   `scaling` constants, and `grid`: the layout of the runs when every run
#'   was made at every field input, and possibly at further inputs such as
#'   those of held-out periods (`NULL` otherwise), which lets [calibrate()]
#'   use the fast Kronecker likelihood.
#' @family data preparation
#' @export
#' @examples
#' d <- koh_data(seb_field, seb_sim)
#' d
#' # the same by name
#' koh_data(seb_field, seb_sim, y = "y", eta = "eta", x = c("temp", "rh", "solar"),
#'          t = c("fan_total_efficiency", "equipment_power_density",
#'                "infiltration_per_exterior_area"))
koh_data <- function(field, sim, y = NULL, eta = NULL, x = NULL, t = NULL, grid_tol = 1e-6) {
  field <- as_numeric_table(field)
  sim <- as_numeric_table(sim)
  cols <- koh_columns(field, sim, y = y, eta = eta, x = x, t = t)
  check_numeric_complete(field, c(cols$y, cols$x), "field")
  check_numeric_complete(sim, c(cols$eta, cols$x_sim, cols$t), "sim")
  n <- nrow(field)
  m <- nrow(sim)
  q <- length(cols$t)
  if (n < 2L) {
    abort_bayesbem(c("{.arg field} must have at least 2 rows.", x = "It has {n}."),
                   "too_few_rows")
  }
  if (m < q + 2L) {
    abort_bayesbem(c("{.arg sim} must have at least q + 2 = {q + 2} rows for {q} calibration parameter{?s}.",
                     x = "It has {m}.",
                     i = "Run the simulator at more design points."),
                   "too_few_rows")
  }
  xf_raw <- as.matrix(field[cols$x])
  xc_raw <- as.matrix(sim[cols$x_sim])
  colnames(xc_raw) <- cols$x
  tc_raw <- as.matrix(sim[cols$t])
  eta_raw <- sim[[cols$eta]]
  scaling <- list(
    y_center = mean(eta_raw),
    y_scale = stats::sd(eta_raw),
    x_min = apply(rbind(xf_raw, xc_raw), 2, min),
    x_max = apply(rbind(xf_raw, xc_raw), 2, max),
    t_min = apply(tc_raw, 2, min),
    t_max = apply(tc_raw, 2, max)
  )
  check_varies(scaling$y_scale, cols$eta, "sim")
  check_varies(scaling$x_max - scaling$x_min, cols$x, "field and sim together")
  check_varies(scaling$t_max - scaling$t_min, cols$t, "sim")
  check_distinct_runs(cbind(xc_raw, tc_raw))
  xf <- scale_x(xf_raw, scaling)
  xc <- scale_x(xc_raw, scaling)
  tc <- scale_t(tc_raw, scaling)
  grid <- grid_layout(xf, xc, tc, grid_tol)
  # on a grid, simulation inputs at field inputs are those (up to rounding)
  if (!is.null(grid)) xc <- grid$x[grid$period, , drop = FALSE]
  structure(
    list(
      y = scale_y(field[[cols$y]], scaling),
      eta = scale_y(eta_raw, scaling),
      xf = xf, xc = xc, tc = tc,
      grid = grid,
      names = cols,
      n = n, m = m, p = length(cols$x), q = q,
      scaling = scaling,
      field = field,
      sim = sim
    ),
    class = "koh_data"
  )
}

# `field` itself when it is a koh_data object, else koh_data(field, sim).
as_koh_data <- function(field, sim) {
  if (inherits(field, "koh_data")) field else koh_data(field, sim)
}

#' @export
print.koh_data <- function(x, ...) {
  cat_lines("{.cls koh_data}: {x$n} field row{?s}, {x$m} simulation row{?s}",
            "* output: {.field {x$names$y}} (field), {.field {x$names$eta}} (simulation)",
            "* {x$p} observable input{?s} x: {.field {x$names$x}}",
            "* {x$q} calibration parameter{?s} t: {.field {x$names$t}}",
            if (!is.null(x$grid)) {
              "* grid design: {x$grid$mt} runs at {x$grid$n_x} inputs, the {x$n} field inputs among them (matched within {signif(x$grid$max_diff, 2)} of their range)"
            })
  invisible(x)
}

# Accepts data frames and numeric matrices; everything else is an error.
as_numeric_table <- function(d, arg = rlang::caller_arg(d), call = rlang::caller_env()) {
  if (is.matrix(d) && is.numeric(d)) {
    d <- as.data.frame(d)
  }
  if (!is.data.frame(d)) {
    abort_bayesbem(c("{.arg {arg}} must be a data frame or a numeric matrix.",
                     x = "It is {.obj_type_friendly {d}}."),
                   "input_type", call = call)
  }
  if (is.null(names(d)) || anyNA(names(d)) || any(names(d) == "") || anyDuplicated(names(d))) {
    abort_bayesbem(c("{.arg {arg}} must have unique, non-empty column names.",
                     i = "Name its columns, e.g. with {.code names(x) <- ...}."),
                   "columns", call = call)
  }
  d
}

# Resolves which columns are y, eta, x and t: by name when given, else by
# position. `x_sim` holds the simulation table's names for the x columns.
koh_columns <- function(field, sim, y, eta, x, t, call = rlang::caller_env()) {
  by_position <- is.null(x)
  y <- y %||% names(field)[1]
  eta <- eta %||% names(sim)[1]
  x <- x %||% setdiff(names(field), y)
  check_has_columns(field, c(y, x), "field", call)
  p <- length(x)
  if (by_position && ncol(sim) < p + 2L) {
    abort_bayesbem(
      c("{.arg sim} must have eta, the {p} observable input{?s} of {.arg field}, and at least one calibration parameter: {p + 2} columns or more.",
        x = "It has {ncol(sim)} column{?s}: the field and simulation tables differ in their number of input columns.",
        i = "Give {.arg sim} the same inputs as {.arg field}, or name the columns with {.arg x} and {.arg t}."),
      "columns", call = call)
  }
  x_sim <- if (by_position) names(sim)[1 + seq_len(p)] else x
  t <- t %||% setdiff(names(sim), c(eta, x_sim))
  check_has_columns(sim, c(eta, x_sim, t), "sim", call)
  if (length(t) < 1L) {
    abort_bayesbem("{.arg sim} must have at least one calibration-parameter column.",
                   "columns", call = call)
  }
  list(y = y, eta = eta, x = x, x_sim = x_sim, t = t)
}

check_has_columns <- function(d, cols, arg, call) {
  missing <- setdiff(cols, names(d))
  if (length(missing) > 0L) {
    abort_bayesbem(c("{.arg {arg}} has no column{?s} {.field {missing}}.",
                     i = "Its columns are {.field {names(d)}}."),
                   "columns", call = call)
  }
}

check_numeric_complete <- function(d, cols, arg, call = rlang::caller_env()) {
  for (col in cols) {
    v <- d[[col]]
    if (!is.numeric(v)) {
      abort_bayesbem(c("Column {.field {col}} of {.arg {arg}} must be numeric.",
                       x = "It is {.obj_type_friendly {v}}.",
                       i = "Convert it before calibrating, e.g. with {.fn as.numeric}."),
                     "non_numeric", call = call)
    }
    bad <- which(!is.finite(v))
    if (length(bad) > 0L) {
      abort_bayesbem(c("Column {.field {col}} of {.arg {arg}} has missing or non-finite values.",
                       x = "{cli::qty(length(bad))}Row{?s} {bad}.",
                       i = "Remove or fill those rows before calibrating."),
                     "missing", call = call)
    }
  }
}

# Two simulation rows with the same inputs and parameters make the emulator
# covariance singular (a deterministic simulator gives them one output).
check_distinct_runs <- function(xt, call = rlang::caller_env()) {
  dup <- which(duplicated(xt))
  if (length(dup) > 0L) {
    first <- which(duplicated(xt, fromLast = TRUE))
    abort_bayesbem(c("{.arg sim} has {length(dup)} duplicated row{?s} (same inputs and parameters): {.val {dup}}.",
                     i = "Average the outputs of repeated runs, or drop the repeats (rows repeated: {.val {first}})."),
                   "duplicated", call = call)
  }
}

check_varies <- function(ranges, cols, where, call = rlang::caller_env()) {
  flat <- cols[!(ranges > 0)]
  if (length(flat) > 0L) {
    abort_bayesbem(c("{cli::qty(length(flat))}Column{?s} {.field {flat}} {?is/are} constant over {where}.",
                     i = "A constant column cannot be scaled and carries no information: drop it."),
                   "constant", call = call)
  }
}
