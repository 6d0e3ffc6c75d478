# Every error the package raises goes through here so that it carries the
# class `bayesbem_error` plus a specific subclass users and tests can catch.
abort_bayesbem <- function(message, type, ..., call = rlang::caller_env()) {
  cli::cli_abort(message, class = c(paste0("bayesbem_error_", type), "bayesbem_error"),
                 ..., call = call)
}

warn_bayesbem <- function(message, type, ...) {
  cli::cli_warn(message, class = c(paste0("bayesbem_warning_", type), "bayesbem_warning"),
                ...)
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
