# Every condition the package raises goes through here so that it carries the
# class `bayesbem_error` (or `bayesbem_warning`) plus a specific subclass that
# users and tests can catch. `.envir` is the caller's frame, where cli
# interpolates `{}` in the message.
abort_bayesbem <- function(message, type, ..., call = rlang::caller_env(),
                           .envir = parent.frame()) {
  cli::cli_abort(message, class = c(paste0("bayesbem_error_", type), "bayesbem_error"),
                 ..., call = call, .envir = .envir)
}

warn_bayesbem <- function(message, type, ..., .envir = parent.frame()) {
  cli::cli_warn(message, class = c(paste0("bayesbem_warning_", type), "bayesbem_warning"),
                ..., .envir = .envir)
}

# Checks that `x` is one positive whole number; `arg` names it in the error.
check_count <- function(x, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!isTRUE(checkmate::check_count(x, positive = TRUE))) {
    abort_bayesbem("{.arg {arg}} must be a positive whole number, not {describe_value(x)}.",
                   "argument", call = call)
  }
  invisible(x)
}

# Checks that `x` is one non-empty string.
check_string <- function(x, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!rlang::is_string(x) || !nzchar(x)) {
    abort_bayesbem("{.arg {arg}} must be a non-empty string, not {describe_value(x)}.",
                   "argument", call = call)
  }
  invisible(x)
}

# Checks that `x` is TRUE or FALSE.
check_bool <- function(x, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!rlang::is_bool(x)) {
    abort_bayesbem("{.arg {arg}} must be {.code TRUE} or {.code FALSE}, not {describe_value(x)}.",
                   "argument", call = call)
  }
  invisible(x)
}

# Checks that `x` is one finite number, non-negative or, with
# `positive = TRUE`, positive; `type` is the error subclass.
check_number <- function(x, type, positive = FALSE, arg = rlang::caller_arg(x),
                         call = rlang::caller_env()) {
  if (!is.numeric(x) || length(x) != 1L || !is.finite(x) || x < 0 || (positive && x == 0)) {
    sign <- if (positive) "positive" else "non-negative"
    abort_bayesbem("{.arg {arg}} must be a {sign} number, not {describe_value(x)}.", type,
                   call = call)
  }
  invisible(x)
}

# One number from `lower` to `upper`.
check_between <- function(x, lower, upper, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!is.numeric(x) || length(x) != 1L || !isTRUE(x >= lower && x <= upper)) {
    abort_bayesbem("{.arg {arg}} must be a number from {lower} to {upper}, not {describe_value(x)}.",
                   "argument", call = call)
  }
}

# Checks that `x` is one number strictly between 0 and 1 (a probability
# level).
check_probability <- function(x, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!is.numeric(x) || length(x) != 1L || !isTRUE(x > 0 && x < 1)) {
    abort_bayesbem("{.arg {arg}} must be a number between 0 and 1, not {describe_value(x)}.",
                   "argument", call = call)
  }
  invisible(x)
}

# What a wrong argument is, for error messages: its value when it is a single
# number or string ("the number 0", "the string \"500\""), else its type.
describe_value <- function(x) {
  if (length(x) == 1L && !is.na(x)) {
    if (is.character(x)) {
      return(sprintf("the string \"%s\"", x))
    }
    if (is.numeric(x)) {
      return(sprintf("the number %s", format(x)))
    }
  }
  cli::format_inline("{.obj_type_friendly {x}}")
}

# match.arg() with a classed error listing the choices: `arg` must be one of
# `choices`, by default the vector given as the calling function's default
# for that argument, which (as with match.arg()) also means its first element.
match_choice <- function(arg, choices = NULL, arg_name = rlang::caller_arg(arg),
                         call = rlang::caller_env()) {
  if (is.null(choices)) {
    caller <- sys.function(sys.parent())
    choices <- eval(formals(caller)[[arg_name]], envir = call)
  }
  if (identical(arg, choices)) {
    return(choices[1])
  }
  if (!rlang::is_string(arg) || !arg %in% choices) {
    # the nearest choice, if a few edits away
    distance <- if (rlang::is_string(arg)) drop(utils::adist(arg, choices)) else Inf
    close <- choices[distance == min(distance) & distance <= max(2, nchar(arg) / 3)]
    abort_bayesbem(c("{.arg {arg_name}} must be one of {.or {.val {choices}}}, not {describe_value(arg)}.",
                     i = if (length(close) > 0L) "Did you mean {.val {close[1]}}?"),
                   "argument", call = call)
  }
  arg
}

# Checks that every element of `dots` (a list of `...` arguments) is named
# with one of `allowed`, the arguments of `where`.
check_dots_in <- function(dots, allowed, where, call = rlang::caller_env()) {
  given <- names(dots) %||% rep("", length(dots))
  unknown <- given[!given %in% allowed]
  if (length(unknown) > 0L) {
    shown <- ifelse(unknown == "", "an unnamed argument", unknown)
    abort_bayesbem(c("{.arg ...} has {cli::qty(length(unknown))}argument{?s} {.arg {shown}} that {where} does not take.",
                     i = "Its arguments are {.arg {allowed}}; check the spelling."),
                   "argument", call = call)
  }
  invisible(dots)
}

# Prints cli-formatted lines to standard output (print methods must write
# there, not to the message stream, so that capture.output() sees them).
cat_lines <- function(..., .envir = parent.frame()) {
  lines <- vapply(c(...), cli::format_inline, character(1), .envir = .envir, USE.NAMES = FALSE)
  cat(lines, sep = "\n")
}

# "a", "a and b", "a, b and c".
and_list <- function(x) {
  if (length(x) < 2L) x else paste(paste(x[-length(x)], collapse = ", "), "and", x[length(x)])
}

# Prints a data frame without row names, doubles rounded to `digits`
# significant digits; one of more than `max_rows` rows (a year of hours) as
# its first 20 rows and its last (a total, where there is one), saying how
# many are left out.
print_rounded <- function(df, digits, max_rows = 50L) {
  num <- vapply(df, is.double, logical(1))
  df[num] <- lapply(df[num], signif, digits = digits)
  n <- nrow(df)
  if (n <= max_rows) {
    return(print(df, row.names = FALSE))
  }
  print(df[c(seq_len(20L), n), , drop = FALSE], row.names = FALSE)
  cat_lines("(rows 21 to {n - 1} of {n} not shown)")
}

