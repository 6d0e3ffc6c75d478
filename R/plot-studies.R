#' Plot a parameter study
#'
#' The paper's Fig 4: for each calibration parameter, box plots of its
#' posterior (whiskers 5-95 %, box 25-75 %, line at the median) for each
#' number of calibrated parameters `k`, in physical units.
#'
#' @param x A `bayesbem_parameter_study` from [study_parameters()].
#' @param ... Unused.
#' @return `plot_parameter_study()` (and `plot(x)`): a ggplot. `plot_parameter_study_data()`:
#'   the data frame it draws, `x$posteriors` with `k` as a factor and
#'   parameters in ranking order.
#' @family studies
#' @family plots
#' @export
#' @examples
#' \donttest{
#' study <- study_parameters(seb_field, seb_sim, k = 1:3, chains = 1, iter = 300,
#'                           refresh = 0)
#' plot_parameter_study(study)
#' }
plot_parameter_study <- function(x) {
  d <- plot_parameter_study_data(x)
  ggplot2::ggplot(d, ggplot2::aes(x = .data$k, group = .data$k)) +
    geom_quantile_box(width = 0.6, fill = colour_of("model_fill"), colour = colour_of("model")) +
    ggplot2::facet_wrap(ggplot2::vars(.data$parameter), scales = "free_y") +
    ggplot2::labs(x = "number of calibrated parameters k", y = "posterior (physical units)") +
    theme_bayesbem()
}

#' @rdname plot_parameter_study
#' @export
plot_parameter_study_data <- function(x) {
  check_plotted(x, "bayesbem_parameter_study", "study_parameters")
  d <- x$posteriors
  d$k <- factor(d$k, levels = paste("k =", x$k), labels = x$k)
  d$parameter <- factor(d$parameter, levels = x$ranking[x$ranking %in% d$parameter])
  d
}

#' @rdname plot_parameter_study
#' @export
plot.bayesbem_parameter_study <- function(x, ...) {
  rlang::check_dots_empty()
  plot_parameter_study(x)
}

#' Plot a prior study
#'
#' The paper's Fig 5: for each calibration parameter, its posterior density
#' under each prior strength, in physical units over the design range.
#'
#' @param x A `bayesbem_prior_study` from [study_priors()].
#' @param ... Unused.
#' @return `plot_prior_study()` (and `plot(x)`): a ggplot. `plot_prior_study_data()`: a data
#'   frame with columns `strength`, `parameter`, `value` and `density` (the
#'   posteriors; see [plot_posteriors_data()]).
#' @family studies
#' @family plots
#' @export
#' @examples
#' \donttest{
#' mu <- c(fan_total_efficiency = 0.6, equipment_power_density = 21.9,
#'         infiltration_per_exterior_area = 0.0011)
#' study <- study_priors(seb_field, seb_sim, strengths = c("flat", "specific"), mu = mu,
#'                       chains = 1, iter = 300, seed = 1, refresh = 0)
#' plot_prior_study(study)
#' }
plot_prior_study <- function(x) {
  d <- plot_prior_study_data(x)
  ggplot2::ggplot(d, ggplot2::aes(.data$value, .data$density, colour = .data$strength)) +
    ggplot2::geom_line() +
    ggplot2::facet_wrap(ggplot2::vars(.data$parameter), scales = "free") +
    ggplot2::scale_colour_manual(values = c(flat = colour_of("prior"), weak = colour_of("model"),
                                            specific = colour_of("data"))) +
    ggplot2::labs(x = "value (physical units)", y = "posterior density", colour = "prior") +
    theme_bayesbem(legend = "bottom")
}

#' @rdname plot_prior_study
#' @export
plot_prior_study_data <- function(x) {
  check_plotted(x, "bayesbem_prior_study", "study_priors")
  x$densities
}

#' @rdname plot_prior_study
#' @export
plot.bayesbem_prior_study <- function(x, ...) {
  rlang::check_dots_empty()
  plot_prior_study(x)
}
