#' Savings per period, with their uncertainty
#'
#' Box plots (box: quartiles; whiskers: 5 % and 95 % quantiles) of the
#' paired posterior draws of a retrofit's savings in each period
#' ([savings()]), with the total and its 90 % interval in the subtitle.
#'
#' @param x A `bayesbem_savings`.
#' @param ... Unused.
#' @return `plot_savings()` (and `plot(x)`): a ggplot. `plot_savings_data()`: a data frame
#'   with one row per period: `period`, the box statistics `q5`, `q25`,
#'   `q50`, `q75`, `q95`, and `mean`; its attribute `total` holds the
#'   total's `mean` and its 90 % interval `q5`, `q95` (as in `summary(x)`).
#' @family plots
#' @family prediction
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' s <- savings(seb_fit, sim, scenario(sim, scale = c(equipment_power_density = 0.7)),
#'              ndraws = 20)
#' plot_savings(s)
#' }
plot_savings <- function(x, ...) {
  rlang::check_dots_empty()
  d <- plot_savings_data(x)
  total <- attr(d, "total")
  ggplot2::ggplot(d, ggplot2::aes(x = .data$period, group = .data$period)) +
    ggplot2::geom_hline(yintercept = 0, colour = colour_of("reference")) +
    geom_quantile_box(width = 0.6, fill = colour_of("savings_fill"), colour = colour_of("savings")) +
    ggplot2::geom_point(ggplot2::aes(y = .data$mean), colour = colour_of("savings"), shape = 4) +
    ggplot2::labs(x = "period", y = "savings (baseline - retrofit)",
                  title = x$scenarios$retrofit$name,
                  subtitle = sprintf("total %s (90 %% interval %s to %s); discrepancy: %s",
                                     signif(total$mean, 3), signif(total$q5, 3),
                                     signif(total$q95, 3), x$discrepancy),
                  caption = "boxes: quartiles, whiskers: 5 % and 95 % of paired posterior draws; crosses: means") +
    theme_bayesbem()
}

#' @export
plot.bayesbem_savings <- function(x, ...) plot_savings(x, ...)

#' @rdname plot_savings
#' @export
plot_savings_data <- function(x, ...) {
  rlang::check_dots_empty()
  check_plotted(x, "bayesbem_savings", "savings")
  n <- ncol(x$savings)
  total <- rowSums(x$savings)
  bounds <- column_intervals(cbind(total), 0.9)
  structure(data.frame(period = factor(seq_len(n)), box_stats(x$savings),
                       mean = colMeans(x$savings)),
            total = data.frame(mean = mean(total), q5 = bounds[, "lower"],
                               q95 = bounds[, "upper"]))
}
