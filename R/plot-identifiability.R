#' Map of what the data determined
#'
#' Each calibration parameter of [identifiability()] placed by how much the
#' data narrowed its prior (x: posterior sd over prior sd) and by how much of
#' its effect the discrepancy holds (y: `|shift|`, in posterior sds, log
#' scale), coloured by verdict; dashed lines mark the verdicts' thresholds
#' (0.5 and 0.8 on x, 2 on y).
#'
#' @param x A `bayesbem_identifiability` from [identifiability()].
#' @return `plot_identifiability()` (and `plot(x)`): a ggplot. `plot_identifiability_data()`:
#'   the table with `abs_shift`, `|shift|` floored at 0.01 for the log axis.
#' @family plots
#' @family discrepancy
#' @export
#' @examples
#' plot_identifiability(identifiability(seb_fit, ndraws = 50))
plot_identifiability <- function(x) {
  d <- plot_identifiability_data(x)
  ggplot2::ggplot(d, ggplot2::aes(.data$sd_ratio, .data$abs_shift, colour = .data$verdict)) +
    ggplot2::geom_vline(xintercept = c(0.5, 0.8), linetype = "dashed", colour = colour_of("reference")) +
    ggplot2::geom_hline(yintercept = 2, linetype = "dashed", colour = colour_of("reference")) +
    ggplot2::geom_point(size = 2.5) +
    ggplot2::geom_text(ggplot2::aes(label = .data$parameter), vjust = -0.9, size = 3,
                       show.legend = FALSE) +
    ggplot2::scale_y_log10() +
    ggplot2::scale_colour_manual(values = c(learnt = colour_of("model"),
                                            `partly learnt` = colour_of("model_light"),
                                            `prior-driven` = colour_of("prior"),
                                            `confounded with the discrepancy` = colour_of("data")),
                                 drop = FALSE, name = NULL) +
    ggplot2::labs(x = "posterior sd / prior sd (1: the data taught nothing)",
                  y = "discrepancy's share of the parameter's effect\n(|shift|, posterior sds)") +
    theme_bayesbem(legend = "bottom")
}

#' @export
plot.bayesbem_identifiability <- function(x, ...) {
  rlang::check_dots_empty()
  plot_identifiability(x)
}

#' @rdname plot_identifiability
#' @export
plot_identifiability_data <- function(x) {
  check_plotted(x, "bayesbem_identifiability", "identifiability")
  d <- as.data.frame(unclass(x))
  d$abs_shift <- pmax(abs(d$shift), 0.01)
  d$verdict <- factor(d$verdict, levels = c("learnt", "partly learnt", "prior-driven",
                                            "confounded with the discrepancy"))
  d
}
