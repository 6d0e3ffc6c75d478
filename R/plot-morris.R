#' Plot Morris screening results
#'
#' The paper's Fig 3: `mu*` against `sigma` for each parameter. Parameters
#' far to the right matter; high `sigma` means non-linear effects or
#' interactions.
#'
#' @param x A `bayesbem_morris` result of [screen_morris()] with
#'   `effects_on = "total"`.
#' @return `plot_morris()` (and `plot(x)`): a ggplot. `plot_morris_data()`: a data frame
#'   with `parameter`, `mu_star`, `sigma` and `rank`.
#' @family design
#' @family plots
#' @export
#' @examples
#' \donttest{
#' if (requireNamespace("sensitivity", quietly = TRUE)) {
#'   sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#'   plot_morris(screen_morris(sim, r = 5, seed = 1))
#' }
#' }
plot_morris <- function(x) {
  d <- plot_morris_data(x)
  ggplot2::ggplot(d, ggplot2::aes(.data$mu_star, .data$sigma, label = .data$parameter)) +
    ggplot2::geom_point(colour = colour_of("model")) +
    ggplot2::geom_text(hjust = -0.08, size = 3, check_overlap = TRUE) +
    ggplot2::scale_x_continuous(expand = ggplot2::expansion(mult = c(0.05, 0.45))) +
    ggplot2::labs(x = "mu* (mean absolute elementary effect)", y = "sigma") +
    theme_bayesbem()
}

#' @export
plot.bayesbem_morris <- function(x, ...) {
  rlang::check_dots_empty()
  plot_morris(x)
}

#' @rdname plot_morris
#' @export
plot_morris_data <- function(x) {
  if (!inherits(x, "bayesbem_morris") || "period" %in% names(x)) {
    abort_bayesbem("{.arg x} must be a result of {.code screen_morris(effects_on = \"total\")}.",
                   "argument")
  }
  if (length(unique(x$output)) > 1L) {
    abort_bayesbem(c("{.arg x} screens {length(unique(x$output))} outputs, each ranked on its own.",
                     i = "Plot one output's rows, e.g. {.code plot_morris(x[x$output == \"{x$output[1]}\", ])}."),
                   "argument")
  }
  as.data.frame(unclass(x))[c("parameter", "mu_star", "sigma", "rank")]
}
