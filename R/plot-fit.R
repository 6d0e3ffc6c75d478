#' Plot a KOH fit
#'
#' The default plot of a calibration: the posteriors of the calibration
#' parameters against their priors. Other types give the trace plots, the
#' calibrated predictions against the measured data, and the paper's
#' three-panel comparison of `eta + delta`, `eta` and `delta / y`.
#'
#' @param x A `bayesbem_fit`.
#' @param type One of `"posteriors"` ([plot_posteriors()]), `"trace"`
#'   ([plot_trace()]), `"predictions"` ([plot_predictions()]) or
#'   `"components"` ([plot_components()]).
#' @param ... Arguments of the plotting function (an unknown one is an error).
#' @return A ggplot.
#' @family plots
#' @export
#' @examples
#' plot(seb_fit)
#' plot(seb_fit, type = "trace")
plot.bayesbem_fit <- function(x, type = c("posteriors", "trace", "predictions", "components"), ...) {
  type <- match_choice(type)
  plotter <- switch(type, posteriors = plot_posteriors, trace = plot_trace,
                    predictions = plot_predictions, components = plot_components)
  check_dots_in(list(...), names(formals(plotter))[-1], sprintf("plot_%s()", type))
  plotter(x, ...)
}
