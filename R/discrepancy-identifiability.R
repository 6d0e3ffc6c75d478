#' Which calibration parameters did the data determine?
#'
#' A low CVRMSE does not make the parameter posteriors trustworthy: the
#' discrepancy can absorb what a parameter should explain (Brynjarsdottir &
#' O'Hagan 2014), and a parameter the data say nothing about keeps its
#' prior. `identifiability()` reports, for each calibration parameter:
#'
#' * how much the data taught: the posterior sd over the prior sd
#'   (`sd_ratio`; both on the design's \[0, 1\] scale, the prior truncated to
#'   it);
#' * how much of the parameter's effect the discrepancy holds: for each
#'   posterior draw, the simulator's sensitivity to the parameter at the
#'   field rows, `s = d eta(x, tf) / d t` (central differences of the
#'   emulator's mean given the runs), and the discrepancy's posterior mean
#'   `delta` there (with any parametric terms of [extend()]); the
#'   discrepancy's projection on `s`, `s' delta / s' s`, is how far the
#'   parameter would have to move for its own effect to take over what the
#'   discrepancy explains. `shift` is its median over draws in posterior sds
#'   of the parameter, `alignment` the median absolute correlation of `s`
#'   and `delta`.
#'
#' With `refit = TRUE` the model is also calibrated without a discrepancy
#' (its precision's prior held at about 1e6, the same data, priors and
#' sampler settings), and `moved` is how far the discrepancy moved each
#' parameter: the posterior mean with it minus without it, in posterior sds.
#' This catches what the projection cannot: a mechanism the simulator lacks
#' that a parameter has partly absorbed (its posterior mean then depends on
#' how much the discrepancy takes).
#'
#' Verdicts: **confounded with the discrepancy** when `|shift| > 2` or
#' `|moved| > 2` (the discrepancy holds more of the parameter's effect than
#' two posterior sds: without it the data would put the parameter outside
#' its posterior's central 95 %; a prior or a mechanism the simulator lacks
#' holds it where it is); otherwise **prior-driven** when `sd_ratio > 0.8`
#' (the data barely narrowed the prior), **partly learnt** when it is above
#' 0.5, and **learnt** below (the posterior is less than half as wide as the
#' prior).
#'
#' On a fit on several outputs, the spreads are the shared parameters' and
#' each output gets its own `shift_<output>` (its own discrepancy's hold on
#' each parameter; a parameter is confounded with the discrepancy of the
#' outputs where `|shift| > 2`) and `informed_by_<output>`: the output's
#' share of what the data say about each parameter, `s' Sigma^-1 s` (the
#' Fisher information of the output's field data about the parameter,
#' `Sigma` their covariance given the runs: emulator, discrepancy and
#' noise; median over draws) over its sum over the outputs.
#'
#' @param fit A `bayesbem_fit`, or a fit on several outputs.
#' @param ndraws Number of posterior draws (evenly spaced) to compute the
#'   sensitivities and projections at (the spreads use all draws).
#' @param refit Also calibrate without the discrepancy (one more fit with the
#'   fit's settings) and report `moved`.
#' @param ... Unused.
#' @return A data frame of class `bayesbem_identifiability`: `parameter`,
#'   `prior_sd`, `posterior_sd` (physical units), `sd_ratio`, `shift`,
#'   `alignment`, with `refit = TRUE` `moved`, and `verdict`; a plain-language summary in `attr(, "summary")`.
#' @family discrepancy
#' @export
#' @examples
#' identifiability(seb_fit, ndraws = 50)
identifiability <- function(fit, ndraws = 100, refit = FALSE, ...) {
  rlang::check_dots_empty()
  check_count(ndraws)
  check_bool(refit)
  check_fit(fit)
  UseMethod("identifiability")
}

#' @export
identifiability.bayesbem_fit <- function(fit, ndraws = 100, refit = FALSE, ...) {
  identifiability_fit(fit, ndraws, refit)
}

# identifiability() of a one-output fit; with `information`, also each
# parameter's Fisher information from the fit's data (median over the
# draws; discrepancy_projection()) in `attr(, "information")`.
identifiability_fit <- function(fit, ndraws, refit, information = FALSE) {
  data <- fit$data
  g <- gp_geometry(data, scale_newdata(data, field_inputs(data)[data$names$x]),
                   fit_structure(fit), fit$emulator$basis)
  draws <- draw_parameters(fit, ndraws)
  per_draw <- lapply(draws, function(par) discrepancy_projection(g, par, data, information))
  shift <- do.call(rbind, lapply(per_draw, `[[`, "shift"))
  alignment <- do.call(rbind, lapply(per_draw, `[[`, "alignment"))
  # the shift in posterior sds of tf on the scale the emulator works on;
  # the spreads in physical units, where the priors are stated
  posterior_sd_unit <- apply(stan_draws(fit, "tf"), 2, stats::sd)
  bounds <- t_bounds(data$scaling)
  span <- bounds$upper - bounds$lower
  prior_sd <- vapply(seq_len(data$q), function(k) {
    prior_sd_scaled(fit$priors$tf[[data$names$t[k]]], bounds$lower[[k]], span[[k]]) * span[[k]]
  }, numeric(1))
  posterior_sd <- unname(apply(parameter_draws(fit), 2, stats::sd))
  out <- data.frame(parameter = data$names$t, prior_sd = prior_sd,
                    posterior_sd = posterior_sd, sd_ratio = posterior_sd / prior_sd,
                    shift = apply(shift, 2, stats::median) / posterior_sd_unit,
                    alignment = apply(alignment, 2, stats::median), row.names = NULL)
  if (refit) out$moved <- moved_by_discrepancy(fit, posterior_sd_unit)
  confounded <- abs(out$shift) > 2 | (if (refit) abs(out$moved) > 2 else FALSE)
  out$verdict <- identifiability_verdict(out$sd_ratio, ifelse(confounded, "the discrepancy", ""))
  structure(out, class = c("bayesbem_identifiability", "data.frame"),
            summary = identifiability_summary(out),
            information = if (information) {
              apply(do.call(rbind, lapply(per_draw, `[[`, "information")), 2, stats::median)
            })
}

# "confounded with <what>" where `confounded` names what, else the band of
# sd_ratio.
identifiability_verdict <- function(sd_ratio, confounded) {
  ifelse(nzchar(confounded), paste("confounded with", confounded),
         ifelse(sd_ratio > 0.8, "prior-driven",
                ifelse(sd_ratio > 0.5, "partly learnt", "learnt")))
}

# identifiability() of a fit on several outputs (see its Details).
#' @export
identifiability.bayesbem_fit_outputs <- function(fit, ndraws = 100, refit = FALSE, ...) {
  outputs <- names(fit$outputs)
  per <- lapply(fit$outputs, identifiability_fit, ndraws = ndraws, refit = FALSE,
                information = TRUE)
  information <- matrix(unlist(lapply(per, attr, "information")), ncol = length(outputs))
  out <- per[[1]][c("parameter", "prior_sd", "posterior_sd", "sd_ratio")]
  for (k in seq_along(outputs)) {
    out[[paste0("informed_by_", outputs[k])]] <- information[, k] / rowSums(information)
  }
  shifts <- vapply(per, `[[`, numeric(nrow(out)), "shift")
  shifts <- matrix(shifts, ncol = length(outputs))
  for (k in seq_along(outputs)) out[[paste0("shift_", outputs[k])]] <- shifts[, k]
  if (refit) {
    posterior_sd_unit <- apply(stan_draws(fit, "tf"), 2, stats::sd)
    out$moved <- moved_by_discrepancy(fit, posterior_sd_unit)
  }
  confounded <- vapply(seq_len(nrow(out)), function(j) {
    which <- outputs[abs(shifts[j, ]) > 2]
    if (length(which) > 0L) return(paste("the", and_list(which), "discrepancy"))
    if (refit && abs(out$moved[j]) > 2) "the discrepancies" else ""
  }, character(1))
  out$verdict <- identifiability_verdict(out$sd_ratio, confounded)
  informs <- vapply(seq_len(nrow(out)), function(j) {
    k <- which.max(information[j, ])
    sprintf("%s %s (%.0f%%)", out$parameter[j], outputs[k], 100 * information[j, k] / sum(information[j, ]))
  }, character(1))
  structure(out, class = c("bayesbem_identifiability", "data.frame"),
            summary = paste(identifiability_summary(out),
                            sprintf("The output that says most about each parameter: %s.",
                                    paste(informs, collapse = "; "))))
}

# How far the discrepancy moved each parameter: the posterior mean with it
# minus the mean of a refit without it (the discrepancy's precision held at
# about 1e6, i.e. a standard deviation of 0.001 standardised units), in
# posterior sds of the fit.
moved_by_discrepancy <- function(fit, posterior_sd) {
  priors <- fit$priors
  priors$lambda_delta <- c(1e4, 1e-2)
  without <- suppressWarnings(refit(fit, priors = priors, progress = FALSE),
                              classes = "bayesbem_warning_convergence")
  mean_tf <- function(f) colMeans(stan_draws(f, "tf"))
  (mean_tf(fit) - mean_tf(without)) / posterior_sd
}

# For one draw: the discrepancy's projection on the simulator's sensitivity
# s to each parameter at the field rows (runs_sensitivity(); in scaled
# parameter units) and its correlation with it; with `information`, what
# the field data say about each parameter, the Fisher information
# s' Sigma^-1 s about tf, Sigma the field outputs' covariance given the
# runs (runs_field(): emulator, discrepancy and noise), in the output's
# standardised units.
discrepancy_projection <- function(g, par, data, information = FALSE) {
  n <- data$n
  cond <- koh_conditional(g, par)
  delta <- cond$mean[n + seq_len(n)]
  if (ncol(g$h) > 0L) delta <- delta + drop(g$h %*% par$gamma)
  s <- runs_sensitivity(g, par)
  list(shift = drop(crossprod(s, delta)) / colSums(s^2),
       alignment = abs(drop(stats::cor(s, delta))),
       information = if (information) {
         colSums(backsolve(chol(runs_field(g, par)$cov), s, transpose = TRUE)^2)
       })
}

# The sd of a prior on the scaled [0, 1] scale: uniform, or a normal (mean
# in physical units, sd scaled) truncated to [0, 1].
prior_sd_scaled <- function(prior, lo, span) {
  if (is.null(prior) || prior$family == "uniform") {
    return(sqrt(1 / 12))
  }
  mu <- (prior$mu - lo) / span
  a <- (0 - mu) / prior$sd
  b <- (1 - mu) / prior$sd
  z <- stats::pnorm(b) - stats::pnorm(a)
  m <- (stats::dnorm(a) - stats::dnorm(b)) / z
  prior$sd * sqrt(1 + (a * stats::dnorm(a) - b * stats::dnorm(b)) / z - m^2)
}

identifiability_summary <- function(x) {
  group <- function(verdict) x$parameter[x$verdict == verdict]
  parts <- c(
    if (length(group("learnt")) > 0L)
      sprintf("The data determined %s.", paste(group("learnt"), collapse = ", ")),
    if (length(group("partly learnt")) > 0L)
      sprintf("The data narrowed %s only in part.", paste(group("partly learnt"), collapse = ", ")),
    if (length(group("prior-driven")) > 0L)
      sprintf("The data say little about %s: %s posterior is close to its prior.",
              paste(group("prior-driven"), collapse = ", "),
              if (length(group("prior-driven")) > 1L) "their" else "its"),
    if (any(startsWith(x$verdict, "confounded")))
      sprintf("The discrepancy holds the effect of %s: %s posterior is not where the data alone would put it (a prior or a missing mechanism holds it there).",
              paste(x$parameter[startsWith(x$verdict, "confounded")], collapse = ", "),
              if (sum(startsWith(x$verdict, "confounded")) > 1L) "their" else "its")
  )
  paste(parts, collapse = " ")
}

#' @export
print.bayesbem_identifiability <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(strwrap(attr(x, "summary")), sep = "\n")
  cat("\n")
  print_rounded(as.data.frame(unclass(x)), digits)
  invisible(x)
}
