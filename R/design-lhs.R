#' Latin hypercube design over parameter ranges
#'
#' A maximin Latin hypercube (package lhs) over the ranges of the given
#' parameters, in physical units: the paper's step 3, with about 10 runs per
#' parameter as a rule of thumb.
#'
#' @param parameters A parameter table (see [bem_parameters()]) with the
#'   parameters to vary, e.g. the top few of [screen_morris()].
#' @param n Number of runs.
#' @param seed Random seed of the design.
#' @return A data frame with `n` rows and one column per parameter.
#' @family design
#' @export
#' @examples
#' design_lhs(bem_parameters()[c(3, 12, 14), ], n = 10, seed = 1)
design_lhs <- function(parameters, n, seed = NULL) {
  params <- check_parameter_table(parameters)
  check_run_count(n)
  design <- maximin_box(n, params$min, params$max, seed)
  stats::setNames(as.data.frame(design), params$parameter)
}

# A maximin Latin hypercube of n points in the box [lower, upper] (one
# column per bound), the design of design_lhs() and design_posterior().
maximin_box <- function(n, lower, upper, seed) {
  unscale_columns(with_seed(seed, lhs::maximinLHS(n, length(lower))), lower, upper)
}

# A design needs two runs at least: a Latin hypercube of one is a point.
check_run_count <- function(n, arg = rlang::caller_arg(n), call = rlang::caller_env()) {
  check_count(n, arg = arg, call = call)
  if (n < 2L) {
    abort_bayesbem("{.arg {arg}} must be at least 2 runs, not {n}.", "argument", call = call)
  }
}
