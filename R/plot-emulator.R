#' The emulator against the simulator at the posterior
#'
#' For each field period (x axis) and posterior draw (side by side within
#' the period), the emulator's interval at the draw's calibration
#' parameters (bar) and the simulator's real output there (point; red when
#' outside the interval). See [validate_emulator()].
#'
#' @param x A `bayesbem_emulator_check` from [validate_emulator()].
#' @return `plot_emulator_check()` (and `plot(x)`): a ggplot. `plot_emulator_check_data()`:
#'   the check's table with `position`, the period offset by draw.
#' @family plots
#' @family diagnostics
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' plot_emulator_check(validate_emulator(seb_fit, sim, ndraws = 5))
#' }
plot_emulator_check <- function(x) {
  d <- plot_emulator_check_data(x)
  ggplot2::ggplot(d, ggplot2::aes(x = .data$position)) +
    ggplot2::geom_linerange(ggplot2::aes(ymin = .data$lower, ymax = .data$upper),
                            colour = colour_of("model"), alpha = 0.6) +
    ggplot2::geom_point(ggplot2::aes(y = .data$simulated, colour = .data$inside), size = 1) +
    ggplot2::scale_colour_manual(values = c(`TRUE` = "black", `FALSE` = colour_of("data")),
                                 labels = c(`TRUE` = "inside", `FALSE` = "outside"),
                                 name = "simulator output") +
    ggplot2::labs(x = "field period", y = x$y,
                  caption = sprintf("bars: emulator's %.0f%% intervals at posterior draws; points: simulator",
                                    100 * x$level)) +
    theme_bayesbem()
}

#' @export
plot.bayesbem_emulator_check <- function(x, ...) {
  rlang::check_dots_empty()
  plot_emulator_check(x)
}

#' @rdname plot_emulator_check
#' @export
plot_emulator_check_data <- function(x) {
  check_plotted(x, "bayesbem_emulator_check", "validate_emulator")
  d <- x$table
  draws <- sort(unique(d$draw))
  offset <- if (length(draws) > 1L) (match(d$draw, draws) - 1) / (length(draws) - 1) - 0.5 else 0
  d$position <- d$period + 0.6 * offset
  d
}
