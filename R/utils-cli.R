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
    abort_bayesbem(c("{.arg {arg}} must be one positive whole number.",
                     x = "It is {.val {format(x)}}."),
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
    abort_bayesbem("{.arg {arg}} must be one {sign} number.", type, call = call)
  }
  invisible(x)
}

# Checks that `x` is one number strictly between 0 and 1 (a probability
# level).
check_probability <- function(x, arg = rlang::caller_arg(x), call = rlang::caller_env()) {
  if (!is.numeric(x) || length(x) != 1L || !isTRUE(x > 0 && x < 1)) {
    abort_bayesbem("{.arg {arg}} must be one number between 0 and 1.", "argument", call = call)
  }
  invisible(x)
}

# Prints cli-formatted lines to standard output (print methods must write
# there, not to the message stream, so that capture.output() sees them).
cat_lines <- function(..., .envir = parent.frame()) {
  lines <- vapply(c(...), cli::format_inline, character(1), .envir = .envir, USE.NAMES = FALSE)
  cat(lines, sep = "\n")
}

# Prints a data frame without row names, doubles rounded to `digits`
# significant digits.
print_rounded <- function(df, digits) {
  num <- vapply(df, is.double, logical(1))
  df[num] <- lapply(df[num], signif, digits = digits)
  print(df, row.names = FALSE)
}
