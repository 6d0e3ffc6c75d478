#' Plot the posterior discrepancy
#'
#' The posterior mean and simultaneous band of what the simulator misses,
#' the residual `y - eta(x, tf)` (discrepancy plus noise, as a share of the
#' measured output, percent, see [discrepancy()]) at every point, along each
#' observable input and along the points' order (time, for field data in
#' time order). Flagged points, where the band excludes zero, are drawn in
#' red.
#'
#' @param x A `bayesbem_discrepancy` from [discrepancy()].
#' @return `plot_discrepancy()` (and `plot(x)`): a ggplot. `plot_discrepancy_data()`: a data
#'   frame with `along` (the input, or `"point order"`), `position`, `point`,
#'   `mean`, `lower`, `upper` (the band; percent of the output) and `flag`;
#'   on several outputs, a first column `output` and a row of panels per
#'   output.
#' @family discrepancy
#' @family plots
#' @export
#' @examples
#' d <- discrepancy(seb_fit, ndraws = 100)
#' plot_discrepancy(d)
#' head(plot_discrepancy_data(d))
plot_discrepancy <- function(x) {
  d <- plot_discrepancy_data(x)
  facets <- if (is.null(d$output)) {
    ggplot2::facet_wrap(ggplot2::vars(.data$along), scales = "free_x")
  } else {
    ggplot2::facet_grid(ggplot2::vars(.data$output), ggplot2::vars(.data$along), scales = "free")
  }
  ggplot2::ggplot(d, ggplot2::aes(.data$position, .data$mean, colour = .data$flag)) +
    ggplot2::geom_hline(yintercept = 0, colour = colour_of("reference")) +
    ggplot2::geom_pointrange(ggplot2::aes(ymin = .data$lower, ymax = .data$upper)) +
    facets +
    ggplot2::scale_colour_manual(values = c(`FALSE` = colour_of("model"), `TRUE` = colour_of("data")),
                                 labels = c(`FALSE` = "interval contains 0",
                                            `TRUE` = "interval excludes 0")) +
    ggplot2::labs(x = NULL, y = "simulator residual (y - eta) / y (%)", colour = NULL,
                  caption = sprintf("posterior mean and %g%% interval", 100 * attr(x, "level"))) +
    theme_bayesbem(legend = "bottom")
}

#' @export
plot.bayesbem_discrepancy <- function(x, ...) {
  rlang::check_dots_empty()
  plot_discrepancy(x)
}

#' @rdname plot_discrepancy
#' @export
plot_discrepancy_data <- function(x) {
  check_plotted(x, "bayesbem_discrepancy", "discrepancy")
  if (is.null(x$output)) {
    return(discrepancy_plot_rows(x))
  }
  # several outputs: each on its own shares, a first column `output`
  outputs <- unique(x$output)
  stack_outputs(lapply(stats::setNames(outputs, outputs), function(k) {
    discrepancy_plot_rows(x[x$output == k, names(x) != "output"])
  }))
}

# plot_discrepancy_data() of one output's rows.
discrepancy_plot_rows <- function(x) {
  x_names <- setdiff(names(x), c("point", "obs", "flag",
                                 grep("^(delta|residual|band)_", names(x), value = TRUE)))
  share <- function(v) 100 * v / share_scale(x$obs)
  along <- c(x_names, "point order")
  rows <- lapply(along, function(a) {
    data.frame(along = a, position = if (a == "point order") x$point else x[[a]],
               point = x$point, mean = share(x$residual_mean), lower = share(x$band_lower),
               upper = share(x$band_upper), flag = x$flag)
  })
  out <- do.call(rbind, rows)
  out$along <- factor(out$along, levels = along)
  out
}
