# Field data and runs of several outputs (meters): a long table per side
# with a column naming each row's output. Each output becomes a one-output
# koh_data() set of its own (its own standardisation, inputs' scaling,
# periods and grid), and the sets share what the calibration shares: the
# calibration parameters, their scales and the runs' design.

# The name of the column that names each row's output: `output` when given
# (checked), else "output" when both tables have a column so named, else
# NULL (one output).
outputs_column <- function(field, sim, output, call = rlang::caller_env()) {
  if (is.null(output)) {
    return(if (all(c("output" %in% names(field), "output" %in% names(sim)))) "output")
  }
  if (!rlang::is_string(output)) {
    abort_bayesbem("{.arg output} must be a column name, not {describe_value(output)}.",
                   "argument", call = call)
  }
  tables <- list(field = field, sim = sim)
  for (side in names(tables)) {
    d <- tables[[side]]
    if (!output %in% names(d)) {
      abort_bayesbem(c("{.arg {side}} has no column {.field {output}} naming each row's output.",
                       i = "Its columns are {.field {names(d)}}."),
                     "columns", call = call)
    }
  }
  output
}

# The outputs named in a table's column, in order of first appearance (a
# factor's levels in their order); missing names are an error.
output_levels <- function(values, column, arg, call) {
  if (!is.character(values) && !is.factor(values)) {
    abort_bayesbem(c("Column {.field {column}} of {.arg {arg}} must name each row's output (character or factor).",
                     x = "It is {.obj_type_friendly {values}}."),
                   "columns", call = call)
  }
  if (anyNA(values) || any(!nzchar(as.character(values)))) {
    abort_bayesbem(c("Column {.field {column}} of {.arg {arg}} has rows without an output.",
                     x = "{cli::qty(sum(is.na(values) | !nzchar(as.character(values))))}Row{?s} {which(is.na(values) | !nzchar(as.character(values)))}."),
                   "missing", call = call)
  }
  if (is.factor(values)) intersect(levels(values), as.character(values)) else unique(values)
}

# koh_data() of several outputs (see its Details). The runs are put in the
# order of the first output's, so that every output's grid has the same
# design; their parameters' scales are chosen once for all outputs.
koh_data_outputs <- function(field, sim, output, args, call = rlang::caller_env()) {
  outputs <- output_levels(field[[output]], output, "field", call)
  check_same_outputs(outputs, output_levels(sim[[output]], output, "sim", call), call)
  split_rows <- function(d, k) d[as.character(d[[output]]) == k, setdiff(names(d), output), drop = FALSE]
  fields <- stats::setNames(lapply(outputs, function(k) split_rows(field, k)), outputs)
  sims <- stats::setNames(lapply(outputs, function(k) split_rows(sim, k)), outputs)
  one <- function(k, scales) {
    with_output_context(k, call, do.call(koh_data_one, c(list(fields[[k]], sims[[k]]),
                                                         utils::modifyList(args, list(scales = scales)),
                                                         list(call = call))))
  }
  # a first pass for the names and each output's own choice of scales (its
  # messages come again in the second)
  first <- suppressMessages(lapply(stats::setNames(outputs, outputs), one, scales = args$scales))
  check_shared_names(first, call)
  t_names <- first[[1]]$names$t
  order_key <- unique(row_keys(as.matrix(sims[[1]][t_names])))
  for (k in outputs) {
    key <- row_keys(as.matrix(sims[[k]][t_names]))
    check_same_runs(k, outputs[1], key, order_key, call)
    sims[[k]] <- sims[[k]][order(match(key, order_key)), , drop = FALSE]
  }
  scales <- shared_scales(lapply(first, function(d) t_scales(d$scaling)))
  data <- lapply(stats::setNames(outputs, outputs), one, scales = scales)
  for (k in outputs) check_output_grid(data[[k]], k, call)
  structure(list(outputs = data, output = output, names = list(outputs = outputs, x = data[[1]]$names$x,
                                                               t = t_names),
                 q = data[[1]]$q, scaling = data[[1]]$scaling),
            class = "bayesbem_outputs")
}

# An error in one output's data names the output.
with_output_context <- function(k, call, expr) {
  withCallingHandlers(expr, bayesbem_error = function(e) {
    abort_bayesbem("The data of output {.val {k}} are not valid.",
                   sub("^bayesbem_error_", "", class(e)[1]), parent = e, call = call)
  })
}

check_same_outputs <- function(field_outputs, sim_outputs, call) {
  no_runs <- setdiff(field_outputs, sim_outputs)
  no_field <- setdiff(sim_outputs, field_outputs)
  if (length(no_runs) + length(no_field) > 0L) {
    abort_bayesbem(c("{.arg field} and {.arg sim} must have the same outputs.",
                     x = if (length(no_runs)) "{.val {no_runs}} {?is/are} in {.arg field} but no run has {?it/them}.",
                     x = if (length(no_field)) "{.val {no_field}} {?is/are} in {.arg sim} but not measured in {.arg field}.",
                     i = "Drop the outputs one side lacks, or check their spelling."),
                   "outputs", call = call)
  }
}

# The outputs share the calibration parameters and observable inputs.
check_shared_names <- function(data, call) {
  for (what in c("t", "x")) {
    sets <- lapply(data, function(d) d$names[[what]])
    differ <- names(sets)[!vapply(sets, identical, logical(1), sets[[1]])]
    if (length(differ) > 0L) {
      label <- c(t = "calibration parameters", x = "observable inputs")[[what]]
      abort_bayesbem(c("Every output must have the same {label}.",
                       x = "{.val {names(sets)[1]}} has {.field {sets[[1]]}}; {.val {differ[1]}} has {.field {sets[[differ[1]]]}}.",
                       i = "Give every output's rows the same columns."),
                     "outputs", call = call)
    }
  }
}

# Every output has the runs of the first: one run per parameter set gives
# every meter (simulate_design()).
check_same_runs <- function(k, first, key, first_key, call) {
  if (!setequal(unique(key), first_key)) {
    abort_bayesbem(c("Output {.val {k}} has other runs than output {.val {first}}.",
                     x = "{length(setdiff(unique(key), first_key))} of its parameter sets {?is/are} not among {.val {first}}'s, and {length(setdiff(first_key, key))} of {.val {first}}'s not among its.",
                     i = "Give every output the outputs of the same runs: one run gives every meter ({.fn simulate_design})."),
                   "outputs", call = call)
  }
}

# The modular fit of several outputs needs each output's runs at its field
# inputs (a grid).
check_output_grid <- function(data, k, call) {
  if (is.null(data$grid)) {
    abort_bayesbem(c("Output {.val {k}}'s runs are not at its field inputs.",
                     x = "Calibrating on several outputs needs, for each, every run at every field input of that output (a grid design).",
                     i = "Run the simulator at each output's field periods ({.fn simulate_design})."),
                   "outputs", call = call)
  }
}

# One scale per parameter for every output, from each output's own choice
# (scales = "auto"): a scale other than the identity when an output's
# emulator gains by it (the first such output's), since an output that
# hardly depends on the parameter loses little on that scale.
shared_scales <- function(scales) {
  out <- scales[[1]]
  for (s in scales[-1]) {
    take <- out == "identity" & s != "identity"
    out[take] <- s[take]
  }
  out
}

#' @export
print.bayesbem_outputs <- function(x, ...) {
  rlang::check_dots_empty()
  sizes <- vapply(x$outputs, function(d) sprintf("%d field rows, %d runs", d$n, d$grid$mt), character(1))
  cat_lines("{.cls bayesbem_outputs}: {length(x$outputs)} output{?s}, named by {.field {x$output}}",
            sprintf("* %s: %s", names(x$outputs), sizes),
            "* {length(x$names$x)} observable input{?s} x: {.field {x$names$x}}",
            "* {x$q} calibration parameter{?s} t, shared: {.field {x$names$t}}",
            scale_lines(t_scales(x$scaling)))
  invisible(x)
}

# A long table of a data set of several outputs, koh_data()'s form: each
# output's `rows(one, k)` (of its data and name) under the output column.
outputs_long_table <- function(data, rows = function(one, k) field_table(one)) {
  do.call(rbind, lapply(names(data$outputs), function(k) {
    cbind(stats::setNames(data.frame(k), data$output), rows(data$outputs[[k]], k))
  }))
}
