#' Calibrated predictions against the measured data
#'
#' Box plots (box: quartiles; whiskers: 5 % and 95 % quantiles) of the
#' posterior draws of the calibrated prediction `eta(x, tf) + delta(x)` at
#' each point, with the measured values as points, one panel per observable
#' input (the paper's Listing 1 loop).
#'
#' @param x A `bayesbem_fit`, or a fit on several outputs: one row of
#'   panels per output, at its field data (`newdata` and `obs` then stay
#'   `NULL`).
#' @param newdata Observable inputs to predict at (default: the field
#'   inputs).
#' @param obs Measured outputs at `newdata` (default: the field outputs when
#'   `newdata` is `NULL`, otherwise none).
#' @template args-ndraws
#' @return `plot_predictions()`: a ggplot. `plot_predictions_data()`: a data
#'   frame with one row per point and input: `point`, `input`, `x`, `width`
#'   (box width), the box statistics `q5`, `q25`, `q50`, `q75`, `q95`, and
#'   `obs`; on several outputs, a first column `output`.
#' @family plots
#' @family prediction
#' @export
#' @examples
#' plot_predictions(seb_fit, ndraws = 100)
plot_predictions <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  d <- plot_predictions_data(x, newdata, obs, ndraws)
  facets <- if (is.null(d$output)) {
    ggplot2::facet_wrap(ggplot2::vars(.data$input), scales = "free_x")
  } else {
    ggplot2::facet_grid(ggplot2::vars(.data$output), ggplot2::vars(.data$input), scales = "free")
  }
  ggplot2::ggplot(d, ggplot2::aes(x = .data$x, group = .data$point)) +
    geom_quantile_box(ggplot2::aes(width = .data$width), fill = colour_of("model_fill"),
                      colour = colour_of("model")) +
    ggplot2::geom_point(ggplot2::aes(y = .data$obs), colour = colour_of("data"), na.rm = TRUE) +
    facets +
    ggplot2::labs(x = "observable input (physical units)",
                  y = if (is.null(d$output)) x$data$names$y else "output",
                  caption = "boxes: calibrated prediction eta + delta; points: measured") +
    theme_bayesbem()
}

#' @rdname plot_predictions
#' @export
plot_predictions_data <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  check_fit(x)
  UseMethod("plot_predictions_data")
}

#' @export
plot_predictions_data.bayesbem_fit_outputs <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  outputs_plot_data(x, plot_predictions_data, newdata, obs, ndraws)
}

#' @export
plot_predictions_data.bayesbem_fit <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  set <- prediction_set(x, newdata, obs)
  stats <- box_stats(predict_draws(x, set$x, ndraws = ndraws)$y)
  x_names <- x$data$names$x
  rows <- lapply(x_names, function(name) {
    value <- set$x[[name]]
    data.frame(point = seq_along(value), input = name, x = value,
               width = 0.04 * max(diff(range(value)), 1e-8),
               stats, obs = set$obs)
  })
  out <- do.call(rbind, rows)
  out$input <- factor(out$input, levels = x_names)
  out
}

#' The three-panel comparison of the paper's Fig 6
#'
#' For each period of the training data (and of held-out data when given),
#' box plots of the posterior draws of three quantities: the calibrated
#' prediction `eta + delta` against the measured output, the simulator part
#' `eta` alone against the measured output, and the discrepancy as a share
#' of the measured output, `100 * delta / y` (percent).
#'
#' @inheritParams plot_predictions
#' @param newdata,obs Held-out observable inputs and their measured outputs,
#'   both or neither.
#' @return `plot_components()`: a ggplot. `plot_components_data()`: a data
#'   frame with `set` (`"training"`, `"held-out"`), `point`, `period` (the
#'   label of the point on the x axis: its month and year, or date, when the
#'   data have a period column, see [koh_data()], else its number),
#'   `component`,
#'   the box statistics `q5` to `q95`, and `obs` (measured output; `NA` for
#'   the discrepancy panel); on several outputs, a first column `output`.
#' @family plots
#' @family prediction
#' @export
#' @examples
#' plot_components(seb_fit, ndraws = 100)
plot_components <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  d <- plot_components_data(x, newdata, obs, ndraws)
  columns <- if (is.null(d$output)) ggplot2::vars(.data$set) else ggplot2::vars(.data$output)
  zero <- data.frame(component = factor(component_labels()[3], levels = component_labels()),
                     y = 0)
  ggplot2::ggplot(d, ggplot2::aes(x = .data$period, group = .data$period)) +
    ggplot2::geom_hline(data = zero, ggplot2::aes(yintercept = .data$y), colour = colour_of("reference")) +
    geom_quantile_box(width = 0.6, fill = colour_of("model_fill"), colour = colour_of("model")) +
    ggplot2::geom_point(ggplot2::aes(y = .data$obs), colour = colour_of("data"), na.rm = TRUE) +
    ggplot2::facet_grid(ggplot2::vars(.data$component), columns, scales = "free",
                        space = "free_x") +
    ggplot2::labs(x = if (is.null(output_fit_list(x)[[1]]$data$names$period)) "point" else "period",
                  y = NULL,
                  caption = "boxes: posterior draws; points: measured output") +
    theme_bayesbem() +
    ggplot2::theme(axis.text.x = ggplot2::element_text(angle = 90, vjust = 0.5, hjust = 1))
}

#' @rdname plot_components
#' @export
plot_components_data <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  check_fit(x)
  UseMethod("plot_components_data")
}

#' @export
plot_components_data.bayesbem_fit_outputs <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  outputs_plot_data(x, plot_components_data, newdata, obs, ndraws)
}

#' @export
plot_components_data.bayesbem_fit <- function(x, newdata = NULL, obs = NULL, ndraws = NULL) {
  sets <- evaluation_sets(x, newdata, obs)
  labels <- component_labels()
  rows <- lapply(names(sets), function(set) {
    s <- sets[[set]]
    draws <- predict_draws(x, s$x, ndraws = ndraws)
    share <- 100 * sweep(draws$delta, 2, s$obs, "/")
    parts <- list(draws$y, draws$eta, share)
    period <- period_labels(x$data, if (set == "training") x$data$field else newdata)
    do.call(rbind, lapply(seq_along(parts), function(i) {
      data.frame(set = set, point = seq_along(s$obs), period = period, component = labels[i],
                 box_stats(parts[[i]]), obs = if (i < 3) s$obs else NA_real_)
    }))
  })
  out <- do.call(rbind, rows)
  out$period <- factor(out$period, levels = unique(out$period))
  out$component <- factor(out$component, levels = labels)
  out$set <- factor(out$set, levels = names(sets))
  out
}

component_labels <- function() c("eta + delta", "eta", "delta / y (%)")

# A plot's data for each output of a fit on several outputs, with a first
# column `output`: the outputs' own field data (other inputs are given
# output by output, on output_fit()).
outputs_plot_data <- function(fit, data_fun, newdata, obs, ndraws, call = rlang::caller_env()) {
  if (!is.null(newdata) || !is.null(obs)) {
    abort_bayesbem(c("On a fit on several outputs, this plot shows each output's field data.",
                     i = "For other inputs, plot one output: {.code output_fit(fit, \"{names(fit$outputs)[1]}\")}."),
                   "argument", call = call)
  }
  out <- stack_outputs(lapply(fit$outputs, data_fun, ndraws = ndraws))
  out$output <- factor(out$output, levels = names(fit$outputs))
  out
}
