# One output's field data and runs (koh_data() of one output): columns by
# name, checks, the period column, standardisation, parameter scales and
# the grid.

# koh_data() of one output, its tables already numeric (see koh_data()).
koh_data_one <- function(field, sim, y = NULL, eta = NULL, x = NULL, t = NULL, period = NULL,
                         grid_tol = NULL, scales = "auto",
                         call = rlang::caller_env()) {
  period <- period_column(field, period, call = call)
  cols <- koh_columns(field[setdiff(names(field), period)], sim, y = y, eta = eta, x = x, t = t,
                      call = call)
  cols$period <- period
  check_numeric_complete(field, c(cols$y, cols$x), "field", call = call)
  check_numeric_complete(sim, c(cols$eta, cols$x_sim, cols$t), "sim", call = call)
  sim <- shared_input_runs(sim, cols, as.matrix(field[cols$x]), call)
  n <- nrow(field)
  m <- nrow(sim)
  q <- length(cols$t)
  if (n < 2L) {
    abort_bayesbem(c("{.arg field} must have at least 2 rows.", x = "It has {n}."),
                   "too_few_rows", call = call)
  }
  if (m < q + 2L) {
    abort_bayesbem(c("{.arg sim} must have at least q + 2 = {q + 2} rows for {q} calibration parameter{?s}.",
                     x = "It has {m}.",
                     i = "Run the simulator at more design points."),
                   "too_few_rows", call = call)
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
    days = noise_reference(xf_raw)
  )
  check_runs_respond(eta_raw, field[[cols$y]], cols$eta, call = call)
  check_units(field[[cols$y]], eta_raw, cols, xf_raw, xc_raw, call = call)
  check_varies(scaling$x_max - scaling$x_min, cols$x, "field and sim together", call = call)
  check_varies(apply(tc_raw, 2, max) - apply(tc_raw, 2, min), cols$t, "sim", call = call)
  scaling$t_scale <- parameter_scales(scales, tc_raw, xc_raw, eta_raw, call = call)
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

#' @export
print.bayesbem_data <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_data}: {x$n} field row{?s}, {x$m} simulation row{?s}",
            "* output: {.field {x$names$y}} (field), {.field {x$names$eta}} (simulation)",
            "* {x$p} observable input{?s} x: {.field {x$names$x}}",
            "* {x$q} calibration parameter{?s} t: {.field {x$names$t}}",
            scale_lines(t_scales(x$scaling)),
            if (!is.null(x$scaling$days)) {
              "* noise variance proportional to each period's {.field days} (mean {signif(x$scaling$days, 3)})"
            },
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
# kWh: 3.6e6), of another meter or of other periods (weekly bills against
# monthly runs); calibrating would only absorb the mismatch in the
# discrepancy. Other periods show as field inputs (`xf`) that are none of
# the runs' periods (`xc`, which the runs repeat) with outputs of another
# size: a factor of 2 already (weeks against months: 4.3).
check_units <- function(y, eta, cols, xf, xc, call = rlang::caller_env()) {
  size <- c(stats::median(abs(y)), stats::median(abs(eta)))
  if (any(size == 0)) {
    return(invisible())
  }
  ratio <- max(size) / min(size)
  periods <- unique(value_keys(xc))
  per_period <- length(periods) <= nrow(xc) / 2
  if (ratio > 2 && per_period && !any(value_keys(xf) %in% periods)) {
    abort_bayesbem(c("The field rows are other periods than the runs': none of the {nrow(xf)} field row{?s} has the inputs of one of the runs' {length(periods)} period{?s}, and their outputs differ by a factor of {signif(ratio, 2)}.",
                     i = "Simulate the measurements' own periods, e.g. {.code bem_simulator(weather, periods = bills)} with each bill's {.field start} and {.field end}, or {.code by = \"week\"} for weekly data."),
                   "periods", call = call)
  }
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

# The runs with one row per input and parameters. Field periods may share
# their inputs (two calm night hours of the same weather, hour and
# weekday), and each run then has a row at each; the emulator takes the
# simulator as a function of the inputs, one output per input, so those
# rows are averaged, said in a message with how much they differed (a
# state the inputs miss, such as the building's stored heat). More rows
# than the field's periods there are a run repeated, an error: two rows
# with the same inputs and parameters make the emulator singular.
shared_input_runs <- function(sim, cols, xf, call = rlang::caller_env()) {
  group <- row_groups(as.matrix(sim[c(cols$x_sim, cols$t)]))
  times <- nth_occurrence(group)
  field_keys <- row_keys(xf)
  periods <- as.vector(table(field_keys)[row_keys(as.matrix(sim[cols$x_sim]))])
  dup <- which(times > ifelse(is.na(periods), 1L, periods))
  if (length(dup) > 0L) {
    first <- which(group %in% group[dup] & times == 1L)
    abort_bayesbem(c("{.arg sim} has {length(dup)} duplicated row{?s} (same inputs and parameters, more than the field periods sharing those inputs): {.val {dup}}.",
                     i = "Average the outputs of repeated runs, or drop the repeats (rows repeated: {.val {first}})."),
                   "duplicated", call = call)
  }
  if (!anyDuplicated(group)) {
    return(sim)
  }
  eta <- sim[[cols$eta]]
  spread <- max(tapply(eta, group, function(e) diff(range(e)))) / stats::sd(eta)
  shared <- which(duplicated(field_keys))
  cli::cli_inform(c(i = "{length(shared)} field period{?s} share{?s/} {?its/their} inputs with an earlier one (row{?s} {shared}): each run's outputs at those periods are averaged, the emulator's one output per input.",
                    " " = "They differ by up to {signif(100 * spread, 2)}% of the runs' sd; if that matters, add an input that tells such periods apart: the heat the building stored, e.g. the previous day's mean temperature ({.fn with_lagged_temperature} on an hourly simulator)."),
                  class = "bayesbem_message_shared_inputs")
  merged <- sim[!duplicated(group), , drop = FALSE]
  merged[[cols$eta]] <- as.vector(tapply(eta, group, mean))
  merged
}

# Runs that all give one output: the simulator does not respond to its
# parameters over their ranges. Where the field differs from that output
# no setting reaches it, calibrate()'s prior-misses refusal.
check_runs_respond <- function(eta, y, col, call = rlang::caller_env()) {
  if (stats::sd(eta) > 0) {
    return(invisible())
  }
  misses <- !isTRUE(all.equal(mean(y), eta[1]))
  abort_bayesbem(c("Every run gives the same {.field {col}}, {format(signif(eta[1], 4))}: the simulator does not respond to its parameters over their ranges.",
                   x = if (misses) "The field's mean is {format(signif(mean(y), 4))}: no setting the runs span reaches it.",
                   i = "Check the building's facts and the output's units (e.g. a heating meter where the model's internal gains cover every loss), widen the parameters' ranges and rerun the design."),
                 if (misses) "prior_misses" else "constant", call = call)
}

check_varies <- function(ranges, cols, where, call = rlang::caller_env()) {
  flat <- cols[!(ranges > 0)]
  if (length(flat) > 0L) {
    abort_bayesbem(c("{cli::qty(length(flat))}Column{?s} {.field {flat}} {?is/are} constant over {where}.",
                     i = "A constant column cannot be scaled and carries no information: drop it."),
                   "constant", call = call)
  }
}
