# Checks of arguments shared by every step: a fit, a table's numeric
# columns.

# A fit from calibrate(), of one output or several.
check_fit <- function(fit, arg = rlang::caller_arg(fit), call = rlang::caller_env()) {
  if (!inherits(fit, "bayesbem_fit")) {
    abort_bayesbem(c("{.arg {arg}} must be a {.cls bayesbem_fit} from {.fn calibrate}.",
                     x = "It is {.obj_type_friendly {fit}}."),
                   "argument", call = call)
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

