#' Posteriors of the calibration parameters against their priors
#'
#' The paper's Fig 5: the posterior density of each calibration parameter in
#' its physical units, with the prior density overlaid (flat, or the
#' truncated normal of an informative prior), over the design range.
#'
#' @param x A `bayesbem_fit`, or a fit on several outputs (the parameters
#'   they share).
#' @param n_grid Number of points at which densities are evaluated.
#' @return `plot_posteriors()`: a ggplot. `plot_posteriors_data()`: a data
#'   frame with columns `parameter`, `value`, `density` and `curve`
#'   (`"posterior"` or `"prior"`).
#' @family plots
#' @export
#' @examples
#' plot_posteriors(seb_fit)
#' head(plot_posteriors_data(seb_fit))
plot_posteriors <- function(x, n_grid = 200) {
  d <- plot_posteriors_data(x, n_grid)
  ggplot2::ggplot(d, ggplot2::aes(.data$value, .data$density, colour = .data$curve,
                                  linetype = .data$curve)) +
    ggplot2::geom_line() +
    ggplot2::facet_wrap(ggplot2::vars(.data$parameter), scales = "free") +
    ggplot2::scale_colour_manual(values = c(posterior = colour_of("model"), prior = colour_of("prior"))) +
    ggplot2::scale_linetype_manual(values = c(posterior = "solid", prior = "dashed")) +
    ggplot2::labs(x = "value (physical units)", y = "density", colour = NULL, linetype = NULL) +
    theme_bayesbem(legend = "bottom")
}

#' @rdname plot_posteriors
#' @export
plot_posteriors_data <- function(x, n_grid = 200) {
  x <- output_fit_list(x)[[1]]
  data <- x$data
  draws <- parameter_draws(x)
  bounds <- t_bounds(data$scaling)
  rows <- lapply(seq_len(data$q), function(k) {
    name <- data$names$t[k]
    post <- stats::density(as.vector(draws[, name]), from = bounds$lower[[k]],
                           to = bounds$upper[[k]], n = n_grid)
    prior <- prior_density(x$priors$tf[[name]], post$x, bounds$lower[[k]], bounds$upper[[k]])
    data.frame(parameter = name, value = c(post$x, post$x),
               density = c(post$y, prior),
               curve = rep(c("posterior", "prior"), each = n_grid))
  })
  out <- do.call(rbind, rows)
  out$parameter <- factor(out$parameter, levels = data$names$t)
  out
}

# Prior density in physical units over [lo, hi], the design range (flat
# when no prior is given). Priors are stated in physical units whatever
# scale the emulator works on (tf_prior_lpdf() in koh_functions.stan).
prior_density <- function(prior, value, lo, hi) {
  if (is.null(prior) || prior$family == "uniform") {
    return(rep(1 / (hi - lo), length(value)))
  }
  mu <- (prior$mu - lo) / (hi - lo)
  mass <- stats::pnorm(1, mu, prior$sd) - stats::pnorm(0, mu, prior$sd)
  stats::dnorm((value - lo) / (hi - lo), mu, prior$sd) / mass / (hi - lo)
}
