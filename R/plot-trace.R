#' Trace plots of a KOH fit
#'
#' The paper's Fig 7: trace plots, one line per chain, of the calibration
#' parameters (physical units), the correlation parameters `beta_eta` and
#' `beta_delta`, and the precisions `lambda_eta`, `lambda_delta` and
#' `lambda_e`, drawn by [bayesplot::mcmc_trace()]. Well-mixed chains look
#' like stationary noise that overlaps.
#'
#' @param x A `bayesbem_fit`, or a fit on several outputs (each output's
#'   variables named as `posterior::as_draws()` names them, `"gas:lambda_e"`).
#' @param variables Variables to show (names as in
#'   `posterior::variables(posterior::as_draws(fit))`); all by default.
#' @return `plot_trace()`: a ggplot. `plot_trace_data()`: a data frame from
#'   [bayesplot::mcmc_trace_data()] (`parameter`, `value`, `chain`,
#'   `iteration`, ...).
#' @family plots
#' @family diagnostics
#' @export
#' @examples
#' plot_trace(seb_fit, variables = c("equipment_power_density", "lambda_e"))
plot_trace <- function(x, variables = NULL) {
  bayesplot::mcmc_trace(trace_draws(x, variables)) +
    theme_bayesbem()
}

#' @rdname plot_trace
#' @export
plot_trace_data <- function(x, variables = NULL) {
  bayesplot::mcmc_trace_data(trace_draws(x, variables))
}

trace_draws <- function(fit, variables) {
  draws <- posterior::as_draws_array(fit)
  variables <- variables %||% setdiff(posterior::variables(draws), "lp__")
  unknown <- setdiff(variables, posterior::variables(draws))
  if (length(unknown) > 0L) {
    abort_bayesbem(c("Unknown variable{?s} {.val {unknown}}.",
                     i = "The fit's variables are {.val {posterior::variables(draws)}}."),
                   "argument")
  }
  posterior::subset_draws(draws, variable = variables)
}
