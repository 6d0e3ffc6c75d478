#' Leave-one-out predictive accuracy of a KOH fit
#'
#' Exact leave-one-out for the Gaussian-process likelihood: for every
#' posterior draw, the log density of each field output given all the other
#' field outputs and the simulation runs, in closed form from the precision
#' matrix of the multivariate normal (`y_i | y_-i ~ N(y_i - (Q r)_i / Q_ii,
#' 1 / Q_ii)`). Because the draws come from the posterior given all the
#' data, they are reweighted by Pareto-smoothed importance sampling
#' ([loo::loo()], as for non-factorised models, Burkner, Gabry and Vehtari
#' 2021). Densities are of the output in physical units, so fits with
#' different simulation tables can be compared.
#'
#' On several outputs the points are every output's field rows, each left
#' out of its own output's data: given the parameters the outputs' data are
#' independent (each has its own discrepancy and noise), so a row's
#' leave-one-out density involves its own output's rows only, and the
#' outputs' draws are paired.
#'
#' @param x A `bayesbem_fit`.
#' @template args-ndraws
#' @param ... Unused.
#' @return A `psis_loo` object from the loo package.
#' @family discrepancy
#' @exportS3Method loo::loo
#' @examples
#' loo::loo(seb_fit, ndraws = 200)
loo.bayesbem_fit <- function(x, ndraws = NULL, ...) {
  rlang::check_dots_empty()
  ll <- do.call(cbind, lapply(output_fit_list(x), loo_log_lik, ndraws = ndraws))
  chains <- kept_chains(x)
  r_eff <- if (is.null(ndraws) && nrow(ll) %% chains == 0L) {
    loo::relative_eff(exp(ll), chain_id = rep(seq_len(chains), each = nrow(ll) / chains))
  } else {
    rep(1, ncol(ll))
  }
  loo::loo(ll, r_eff = r_eff)
}

# Draws by field rows of log p(y_i | y_-i, eta), physical units.
loo_log_lik <- function(fit, ndraws = NULL) {
  g <- gp_geometry(fit$data, structure = fit_structure(fit))
  ll <- vapply(draw_parameters(fit, ndraws), function(par) loo_log_density(g, par),
               numeric(fit$data$n))
  t(matrix(ll, nrow = fit$data$n)) - log(fit$data$scaling$y_scale)
}

#' Did the extension help? Compare two fits of the same field data
#'
#' Measures the gain of `b` (typically from [extend()]) over `a`:
#' * `elpd`: the difference in expected log predictive density by exact
#'   leave-one-out with PSIS ([loo.bayesbem_fit()]), `b` minus `a`, with its
#'   standard error from the pointwise differences; a difference above two
#'   standard errors is a clear gain. `pareto_k_max` is the largest Pareto
#'   k of the two PSIS fits: above 0.7 the importance weights of some
#'   points are unreliable (see [loo::pareto-k-diagnostic]) and the ELPD of
#'   those points is approximate;
#' * `metrics`: CVRMSE and NMBE (ASHRAE Guideline 14) of both fits on the
#'   field data, and on the held-out `newdata` when given;
#' * `discrepancy`: the posterior mean of the discrepancy's standard
#'   deviation `1 / sqrt(lambda_delta)` (output units) in each fit, and its
#'   shrinkage `1 - b / a`;
#' * `bias`: when the true calibration parameters are known (synthetic
#'   data, see [simulate_field()]), each parameter's posterior mean minus the
#'   truth in both fits.
#'
#' On fits on several outputs the ELPD is over every output's field rows
#' ([loo.bayesbem_fit()]), and `metrics` and `discrepancy` have a row per
#' output (a first column `output`); held-out data are an output's own, so
#' they are compared output by output ([output_fit()]).
#'
#' @param a,b Two `bayesbem_fit`s of the same field outputs.
#' @param newdata,obs Optional held-out data: a data frame with the
#'   observable inputs and any covariates of the fits' discrepancy terms, and
#'   the measured output of each of its rows.
#' @param truth Optional named list or vector of the true calibration
#'   parameters, physical units.
#' @template args-ndraws
#' @return An object of class `bayesbem_comparison`: a list with `elpd` (a data
#'   frame with `elpd_a`, `elpd_b`, `diff`, `se`, `pareto_k_max`), `metrics`, `discrepancy`,
#'   `bias` and the one-line `verdict`.
#' @family discrepancy
#' @export
#' @examples
#' \donttest{
#' working <- data.frame(working_days = c(22, 20, 21, 22, 22, 20, 23, 21, 21, 23, 20, 21))
#' ext <- extend(seb_fit, with = "working_days", covariates = working, refresh = 0)
#' compare_fits(seb_fit, ext, ndraws = 200)
#' }
compare_fits <- function(a, b, newdata = NULL, obs = NULL, truth = NULL, ndraws = NULL) {
  check_fit(a)
  check_fit(b)
  pairs <- paired_outputs(a, b)
  # loo's Pareto-k warnings are reported as pareto_k_max instead
  loos <- lapply(list(a, b), function(fit) suppressWarnings(loo.bayesbem_fit(fit, ndraws)))
  pointwise <- vapply(loos, function(l) l$pointwise[, "elpd_loo"], numeric(nrow(loos[[1]]$pointwise)))
  diff <- pointwise[, 2] - pointwise[, 1]
  elpd <- data.frame(elpd_a = sum(pointwise[, 1]), elpd_b = sum(pointwise[, 2]),
                     diff = sum(diff), se = sqrt(length(diff) * stats::var(diff)),
                     pareto_k_max = max(vapply(loos, function(l) max(l$diagnostics$pareto_k),
                                               numeric(1))))
  if (length(pairs) > 1L && !is.null(newdata)) {
    abort_bayesbem(c("On fits on several outputs, held-out data belong to one output.",
                     i = "Compare each output's held-out predictions with {.code calibration_metrics(output_fit(b, \"{names(pairs)[1]}\"), newdata, obs)}."),
                   "argument")
  }
  per_output <- function(tool) {
    tables <- lapply(pairs, function(pair) tool(pair$a, pair$b))
    if (length(pairs) > 1L) stack_outputs(tables) else tables[[1]]
  }
  out <- list(
    elpd = elpd,
    metrics = per_output(function(a, b) comparison_metrics(a, b, newdata, obs, ndraws)),
    discrepancy = per_output(comparison_discrepancy),
    bias = if (!is.null(truth)) comparison_bias(a, b, truth)
  )
  out$verdict <- if (elpd$diff > 2 * elpd$se) {
    sprintf("b predicts better than a: ELPD difference %.1f (SE %.1f).", elpd$diff, elpd$se)
  } else if (elpd$diff < -2 * elpd$se) {
    sprintf("b predicts worse than a: ELPD difference %.1f (SE %.1f).", elpd$diff, elpd$se)
  } else {
    sprintf("No clear difference: ELPD difference %.1f (SE %.1f) is within two standard errors.",
            elpd$diff, elpd$se)
  }
  structure(out, class = "bayesbem_comparison")
}

# The one-output fits of `a` and `b`, paired by output: the two fits must
# have the same outputs and, output by output, the same field data.
paired_outputs <- function(a, b, call = rlang::caller_env()) {
  fits <- list(a = output_fit_list(a), b = output_fit_list(b))
  observed <- function(fits) lapply(fits, function(f) f$data$field[[f$data$names$y]])
  if (!identical(names(fits$a), names(fits$b)) || !identical(observed(fits$a), observed(fits$b))) {
    abort_bayesbem(c("{.arg a} and {.arg b} must be fits of the same field outputs.",
                     i = "Leave-one-out comparisons need the same data; compare other fits on held-out data with {.fn calibration_metrics}."),
                   "argument", call = call)
  }
  k <- names(fits$a) %||% "output"
  stats::setNames(Map(function(a, b) list(a = a, b = b), fits$a, fits$b), k)
}

comparison_metrics <- function(a, b, newdata, obs, ndraws, call = rlang::caller_env()) {
  check_held_out(newdata, obs, a$data, call = call)
  rows <- lapply(list(a = a, b = b), held_out_metrics, newdata = newdata, obs = obs,
                 ndraws = ndraws)
  do.call(rbind, Map(function(name, m) data.frame(fit = name, m), names(rows), rows))
}

# The posterior mean of the discrepancy's standard deviation in each of two
# one-output fits (output units), and its shrinkage.
comparison_discrepancy <- function(a, b) {
  delta_sd <- vapply(list(a, b), function(fit) {
    mean(1 / sqrt(stan_draws(fit, "lambda_delta"))) * fit$data$scaling$y_scale
  }, numeric(1))
  data.frame(delta_sd_a = delta_sd[1], delta_sd_b = delta_sd[2],
             shrinkage = 1 - delta_sd[2] / delta_sd[1])
}

comparison_bias <- function(a, b, truth, call = rlang::caller_env()) {
  truth <- unlist(truth)
  shared <- intersect(names(truth), intersect(a$data$names$t, b$data$names$t))
  if (length(shared) == 0L) {
    abort_bayesbem(c("{.arg truth} names none of the calibration parameters both fits share.",
                     i = "They are {.field {intersect(a$data$names$t, b$data$names$t)}}."),
                   "argument", call = call)
  }
  means <- lapply(list(a, b), function(fit) colMeans(parameter_draws(fit, shared)))
  data.frame(parameter = shared, truth = truth[shared], bias_a = means[[1]] - truth[shared],
             bias_b = means[[2]] - truth[shared], row.names = NULL)
}

#' @export
print.bayesbem_comparison <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat(x$verdict, "\n\n")
  for (part in c("elpd", "metrics", "discrepancy", "bias")) {
    if (is.null(x[[part]])) next
    cat(part, ":\n", sep = "")
    print_rounded(x[[part]], digits)
    cat("\n")
  }
  invisible(x)
}
