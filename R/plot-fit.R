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
  check_dots_in(list(...), current_arguments(plotter)[-1], sprintf("plot_%s()", type))
  plotter(x, ...)
}

# Box-plot statistics of each column of a draws matrix: whiskers at the 5 %
# and 95 % quantiles, box at the quartiles.
box_stats <- function(draws) {
  as.data.frame(column_quantiles(draws, c(0.05, 0.25, 0.5, 0.75, 0.95)))
}

geom_quantile_box <- function(mapping, ...) {
  ggplot2::geom_boxplot(
    mapping = ggplot2::aes(ymin = .data$q5, lower = .data$q25, middle = .data$q50,
                           upper = .data$q75, ymax = .data$q95),
    stat = "identity", ...)
}
