#' Field and simulation data for a KOH calibration
#'
#' Combines measured (field) data and simulation runs in the layout of Chong
#' and Menberg (2018), checks them, and scales them as the method requires.
#'
#' The field table holds the measured output `y` and the `p` observable
#' inputs `x`. The simulation table holds the simulator output `eta`, the
#' same `p` inputs, and the `q` calibration parameters `t` of each run. The
#' outputs are named: by default the columns called `y` and `eta` (as
#' [simulate_field()] and [simulate_design()] write them; `eta` may also
#' carry the field output's name), else give `y` and `eta` (the paper's
#' files: `y = "yf", eta = "yc"`); a table without them is an error that
#' lists its columns. `x` is every other field column, matched in `sim` by
#' name, and `t` every other simulation column.
#' An input in one table but not the other is an error, and so is a
#' simulation column taken for a parameter that behaves like an input (one
#' value per input setting). Only when no field input name is in `sim` (the
#' paper's layout, `xf1` against `xc1`) are the simulation inputs taken by
#' position, after `eta`. Name the columns with `y`, `eta`, `x` and `t` to
#' choose them yourself.
#'
#' Simulation rows must be distinct: repeated runs with the same inputs and
#' parameters make the emulator's covariance singular; average them first.
#'
#' Scaling (undone for every number shown to users):
#' * `y` and `eta` are standardised with the mean and standard deviation of
#'   `eta`;
#' * each `x` column is mapped to \[0, 1\] with its minimum and maximum over
#'   field and simulation rows together;
#' * each `t` column is put on its scale (`scales`) and then mapped to
#'   \[0, 1\] with its minimum and maximum over the simulation design.
#'
#' A parameter's scale is where the emulator works with it; its prior stays
#' in physical units (a flat prior is flat in the parameter itself, as in
#' the paper), by a change of variables in the Stan program. The emulator's
#' mean is linear in the parameters, and an output proportional to `1 / t`
#' (fan power against fan efficiency) is far from linear in `t`: the
#' emulator's error along that curve then leaves the posterior with several
#' modes. `scales = "auto"` (the default) puts a positive parameter on the
#' log or reciprocal scale when that lowers by at least a fifth the error
#' with which the least-squares fit of the runs' output on the inputs and
#' parameters (the emulator's mean) predicts each run left out, and keeps
#' the others as they are. Runs left out, not the fit's residuals: for a
#' parameter whose range reaches down to 0 (infiltration), such a scale
#' puts the run nearest 0 far from all others, where a fit to every run
#' matches it but the emulator has nothing to learn from. On the case
#' study it puts fan efficiency, whose fan power goes as its reciprocal, on
#' the reciprocal scale; what that does to convergence is measured in the
#' package's benchmarks (`bench/RESULTS.md`, "Reliability").
#' `scales = "identity"` is the paper's model.
#'
#' @section Several outputs: Field data and runs of several outputs (meters:
#'   electricity and gas bills, say) come as long tables with a column
#'   naming each row's output, `output` by default. Each output then gets a
#'   data set of its own, as above: its output standardised on its own
#'   (bills stay in their units), its own periods (a gas meter read on
#'   other days, a month without a bill) and its own grid; the outputs share
#'   the calibration parameters, their scales (with `scales = "auto"`, a
#'   parameter takes the scale the first output whose emulator gains by one
#'   chose) and the runs: every output needs the outputs of the same runs
#'   (one run gives every meter, as [simulate_design()] writes them), each
#'   at all of its field inputs. An output one table has and the other
#'   lacks is an error that names it.
#' @param field A data frame (or numeric matrix) of field data.
#' @param sim A data frame (or numeric matrix) of simulation runs.
#' @param y,eta Names of the output column in `field` and in `sim`; by
#'   default `"y"` and `"eta"` (or, in `sim`, the field output's name).
#' @param x Names of the observable-input columns, present in both tables.
#' @param t Names of the calibration-parameter columns in `sim`.
#' @param period Name of a `field` column of class `Date` or `POSIXct` that
#'   dates each row (e.g. the first day of each billing month). It is not an
#'   input: plots label the rows with it. By default the field's one such
#'   column, if it has one.
#' @param grid_tol Tolerance, on the scaled \[0, 1\] input scale, within
#'   which a simulation row's inputs count as a field row's. When every run
#'   has one row at each field input within this tolerance, the design is a
#'   grid: the simulation inputs are then taken to be the field inputs
#'   exactly, `print()` reports the largest difference, and [calibrate()]
#'   can use the fast grid likelihood. By default (`NULL`) rounding is
#'   matched (`1e-6`: tables written separately differ in the last digits),
#'   and failing that differences up to 5 % of each input's range, with a
#'   message naming them: field weather computed apart from the runs'
#'   (e.g. bills' months averaged from another copy of the weather file)
#'   differs by that much, and without the match the fit would take the
#'   dense likelihood, hours instead of seconds. Use `0` to require
#'   identical values.
#' @param scales `"auto"` (see Details), `"identity"` (every parameter as
#'   it is, as in the paper), or a named character vector giving some
#'   parameters `"identity"`, `"log"` or `"reciprocal"` (the others keep
#'   the identity), e.g. `c(fan_total_efficiency = "reciprocal")`. Reports
#'   and draws are always in physical units.
#' @param output Name of the column of both tables that names each row's
#'   output (see "Several outputs"); by default `"output"` when both tables
#'   have it, else there is one output.
#' @return An object of class `bayesbem_data`: the scaled matrices `y`, `eta`,
#'   `xf`, `xc`, `tc`, the column names, the sizes `n`, `m`, `p`, `q`, the
#'   `scaling` constants, and `grid`: the layout of the runs when every run
#'   was made at every field input, and possibly at further inputs such as
#'   those of held-out periods (`NULL` otherwise), which lets [calibrate()]
#'   use the fast Kronecker likelihood. With several outputs, an object of
#'   class `bayesbem_outputs`: `outputs`, the `bayesbem_data` of each output
#'   by name, and the names and scaling they share.
#' @family data preparation
#' @export
#' @examples
#' d <- koh_data(seb_field, seb_sim)
#' d
#' # the same by name
#' koh_data(seb_field, seb_sim, y = "y", eta = "eta", x = c("temp", "rh", "solar"),
#'          t = c("fan_total_efficiency", "equipment_power_density",
#'                "infiltration_per_exterior_area"))
koh_data <- function(field, sim, y = NULL, eta = NULL, x = NULL, t = NULL, period = NULL,
                     grid_tol = NULL, scales = "auto", output = NULL) {
  field <- as_numeric_table(field)
  sim <- as_numeric_table(sim)
  output <- outputs_column(field, sim, output)
  if (!is.null(output)) {
    args <- list(y = y, eta = eta, x = x, t = t, period = period, grid_tol = grid_tol,
                 scales = scales)
    return(koh_data_outputs(field, sim, output, args))
  }
  period <- period_column(field, period)
  cols <- koh_columns(field[setdiff(names(field), period)], sim, y = y, eta = eta, x = x, t = t)
  cols$period <- period
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
    x_max = apply(rbind(xf_raw, xc_raw), 2, max)
  )
  check_varies(scaling$y_scale, cols$eta, "sim")
  check_units(field[[cols$y]], eta_raw, cols)
  check_varies(scaling$x_max - scaling$x_min, cols$x, "field and sim together")
  check_varies(apply(tc_raw, 2, max) - apply(tc_raw, 2, min), cols$t, "sim")
  check_distinct_runs(cbind(xc_raw, tc_raw))
  scaling$t_scale <- parameter_scales(scales, tc_raw, xc_raw, eta_raw)
  on_scale <- tc_raw
  for (k in cols$t) on_scale[, k] <- scale_functions[[scaling$t_scale[[k]]]]$to(tc_raw[, k])
  scaling$t_min <- apply(on_scale, 2, min)
  scaling$t_max <- apply(on_scale, 2, max)
  xf <- scale_x(xf_raw, scaling)
  xc <- scale_x(xc_raw, scaling)
  tc <- scale_t(tc_raw, scaling)
  grid <- find_grid(xf, xc, tc, grid_tol, cols$x)
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
    class = "bayesbem_data"
  )
}

# The field table's output, inputs and period columns, as koh_data() takes them.
field_table <- function(data) {
  data$field[c(data$names$y, data$names$x, data$names$period)]
}

# `field` itself when it is a bayesbem_data or bayesbem_outputs object, else
# koh_data(field, sim).
as_koh_data <- function(field, sim) {
  if (inherits(field, c("bayesbem_data", "bayesbem_outputs"))) field else koh_data(field, sim)
}

#' @export
print.bayesbem_data <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_data}: {x$n} field row{?s}, {x$m} simulation row{?s}",
            "* output: {.field {x$names$y}} (field), {.field {x$names$eta}} (simulation)",
            "* {x$p} observable input{?s} x: {.field {x$names$x}}",
            "* {x$q} calibration parameter{?s} t: {.field {x$names$t}}",
            scale_lines(t_scales(x$scaling)),
            if (!is.null(x$names$period)) {
              "* rows dated by {.field {x$names$period}}: {period_labels(x)[1]} to {period_labels(x)[x$n]}"
            },
            if (!is.null(x$grid)) {
              "* grid design: {x$grid$mt} runs at {x$grid$n_x} inputs, the {x$n} field inputs among them (matched within {signif(x$grid$max_diff, 2)} of their range)"
            },
            "* {.fn calibrate} by default: {default_path(x)}")
  invisible(x)
}

# One line per scale other than the identity, e.g. "fitted on the
# reciprocal scale: fan_total_efficiency".
scale_lines <- function(scales) {
  vapply(setdiff(unique(scales), "identity"), function(scale) {
    paste0("* fitted on the ", scale, " scale: ", paste(names(scales)[scales == scale], collapse = ", "))
  }, character(1), USE.NAMES = FALSE)
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

# The name of the field's date column: `period` when given (checked), else
# the one Date or POSIXct column, else NULL.
period_column <- function(field, period, call = rlang::caller_env()) {
  is_date <- vapply(field, function(v) inherits(v, c("Date", "POSIXct")), logical(1))
  if (is.null(period)) {
    if (sum(is_date) > 1L) {
      abort_bayesbem(c("{.arg field} has more than one date column: {.field {names(field)[is_date]}}.",
                       i = "Name the one that dates the rows with {.arg period}, and drop the others."),
                     "columns", call = call)
    }
    return(if (any(is_date)) names(field)[is_date])
  }
  if (!rlang::is_string(period) || !period %in% names(field) || !is_date[[period]]) {
    abort_bayesbem(c("{.arg period} must name a column of {.arg field} of class {.cls Date} or {.cls POSIXct}.",
                     i = "Its date columns: {.field {names(field)[is_date]}}{if (!any(is_date)) 'none'}; convert one with {.fn as.Date}."),
                   "columns", call = call)
  }
  if (anyNA(field[[period]])) {
    abort_bayesbem("Column {.field {period}} of {.arg field} has missing dates.", "missing", call = call)
  }
  period
}

# Labels of rows for plots: their dates when `rows` (a data frame with the
# fit's columns) has the data's period column ("Jan 2013" when every date is
# a first of the month), else the row numbers.
period_labels <- function(data, rows = data$field) {
  period <- data$names$period
  if (is.null(period) || !period %in% names(rows)) {
    return(as.character(seq_len(nrow(rows))))
  }
  dates <- as.Date(rows[[period]])
  if (!all(format(dates, "%d") == "01")) {
    return(format(dates, "%Y-%m-%d"))
  }
  # month.abb, not %b, so that labels do not depend on the locale
  paste(month.abb[as.integer(format(dates, "%m"))], format(dates, "%Y"))
}

# Resolves which columns are y, eta, x and t. Named x and t are taken as
# given. Otherwise x is every field column but y, found in `sim` by name; only
# when none of those names is in `sim` (the paper's CSVs: xf1 vs xc1) are the
# simulation inputs taken by position. `x_sim` holds the simulation table's
# names for the x columns.
koh_columns <- function(field, sim, y, eta, x, t, call = rlang::caller_env()) {
  y <- y %||% output_column(field, "y", "field", setdiff(names(field), names(sim)), call)
  eta <- eta %||% output_column(sim, c("eta", y), "sim", character(), call)
  named_x <- !is.null(x)
  x <- x %||% setdiff(names(field), y)
  check_has_columns(field, c(y, x), "field", call)
  x_sim <- if (named_x || any(x %in% names(sim))) x else positional_inputs(sim, x, call)
  check_inputs_in_sim(sim, x_sim, call)
  named_t <- !is.null(t)
  t <- t %||% setdiff(names(sim), c(eta, x_sim))
  check_has_columns(sim, c(eta, x_sim, t), "sim", call)
  if (length(t) < 1L) {
    abort_bayesbem("{.arg sim} must have at least one calibration-parameter column.",
                   "columns", call = call)
  }
  if (!named_t) check_no_stray_inputs(sim, x_sim, t, call)
  list(y = y, eta = eta, x = x, x_sim = x_sim, t = t)
}

# Bills and runs an order of magnitude apart are in other units (J against
# kWh: 3.6e6) or of another meter; calibrating would only absorb the
# mismatch in the discrepancy.
check_units <- function(y, eta, cols, call = rlang::caller_env()) {
  size <- c(stats::median(abs(y)), stats::median(abs(eta)))
  if (any(size == 0)) {
    return(invisible())
  }
  ratio <- max(size) / min(size)
  if (ratio > 10) {
    abort_bayesbem(c("The field output and the runs' output differ by a factor of {signif(ratio, 2)}: are they in the same units?",
                     x = "{.field {cols$y}} in {.arg field} has median size {signif(size[1], 3)}, {.field {cols$eta}} in {.arg sim} {signif(size[2], 3)}.",
                     i = "Convert one of them (J to kWh: divide by 3.6e6), or check that both are the same meter."),
                   "units", call = call)
  }
}

# The output column of a table by default: the first of `candidates` it
# has. Taking the first column instead made a table written `temp, rh,
# solar, kwh` calibrate temperature.
output_column <- function(d, candidates, arg, likely, call) {
  found <- intersect(candidates, names(d))
  if (length(found) == 0L) {
    name <- c(field = "y", sim = "eta")[[arg]]
    example <- sprintf('%s = "%s"', name, if (length(likely) == 1L) likely else "<column>")
    abort_bayesbem(c("{.arg {arg}} has no column {.field {candidates[1]}}, the output.",
                     i = "Its columns are {.field {names(d)}}.",
                     i = "Name its output column, e.g. {.code {example}}, or rename it."),
                   "columns", call = call)
  }
  found[1]
}

# The paper's layout: the p simulation inputs follow eta.
positional_inputs <- function(sim, x, call) {
  p <- length(x)
  if (ncol(sim) < p + 2L) {
    abort_bayesbem(
      c("{.arg sim} must have eta, the {p} observable input{?s} of {.arg field}, and at least one calibration parameter: {p + 2} columns or more.",
        x = "It has {ncol(sim)} column{?s}: the field and simulation tables differ in their number of input columns.",
        i = "Give {.arg sim} the same inputs as {.arg field}, or name the columns with {.arg x} and {.arg t}."),
      "columns", call = call)
  }
  names(sim)[1 + seq_len(p)]
}

# Field inputs matched by name must all be in `sim`.
check_inputs_in_sim <- function(sim, x_sim, call) {
  missing <- setdiff(x_sim, names(sim))
  if (length(missing) > 0L) {
    abort_bayesbem(c("{cli::qty(length(missing))}Field input{?s} {.field {missing}} {?is/are} not in {.arg sim}.",
                     i = "Inputs are matched by name: give {.arg sim} the same input columns as {.arg field}, or drop {cli::qty(length(missing))}{?it/them} from {.arg field}."),
                     "columns", call = call)
  }
}

# A column of `sim` that is in no field column but takes one value per input
# setting (constant among the rows at the same x, wherever an x repeats) is
# an observable input the field table lacks, not a calibration parameter.
check_no_stray_inputs <- function(sim, x_sim, t, call) {
  key <- row_keys(as.matrix(sim[x_sim]))
  repeated <- key %in% key[duplicated(key)]
  if (!any(repeated)) {
    return(invisible())
  }
  # constant columns are left to check_varies()
  stray <- t[vapply(t, function(col) {
    values <- split(sim[[col]][repeated], key[repeated])
    length(unique(sim[[col]])) > 1L && all(vapply(values, function(v) all(v == v[1]), logical(1)))
  }, logical(1))]
  if (length(stray) > 0L) {
    n <- length(stray)
    abort_bayesbem(c("{cli::qty(n)}Column{?s} {.field {stray}} of {.arg sim} {?is/are} not in {.arg field} but take{?s/} one value per input setting, like an observable input.",
                     i = "{cli::qty(n)}Add {?it/them} to {.arg field}, drop {?it/them} from {.arg sim}, or name the columns with {.arg x} and {.arg t}."),
                   "columns", call = call)
  }
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
    if (length(v) > 0L && all(is.na(v))) {
      abort_bayesbem(c("Column {.field {col}} of {.arg {arg}} is missing: all its values are {.code NA}.",
                       i = "Give its values; every row needs them."),
                     "missing", call = call)
    }
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
