#' Savings of a retrofit, with honest uncertainty
#'
#' `savings()` prices a retrofit with the calibrated model (IPMVP Option D,
#' calibrated simulation): the baseline and the retrofit [scenario()] are
#' simulated at the same posterior draws (paired), so the uncertainty of the
#' calibration parameters that both share cancels where it should and
#' remains where the retrofit acts on it. Savings are the baseline's use
#' less the retrofit's, per period and in total, in the output's units.
#' With both scenarios under a typical year's weather, they are the
#' normalised savings.
#'
#' What the retrofit does to the discrepancy, the part of the measured use
#' the simulator misses, is an assumption the data cannot settle:
#' * `"same"` (default): the discrepancy stays as it is (a missing load the
#'   retrofit does not touch); it cancels from the savings, which are then
#'   the simulator's.
#' * `"proportional"`: the discrepancy scales with the simulated use (a
#'   simulator that misses a share of the loads the retrofit reduces).
#' * `"none"`: the simulator alone, without the discrepancy in either.
#'
#' Savings are of the expected use (no observation noise).
#'
#' On a fit on several outputs (with scenarios whose simulators give them
#' all), each output's savings come from the same runs, one per draw and
#' scenario for every output, and `total` weights them into a total (site
#' energy, or cost with prices per unit of each output) draw by draw.
#'
#' @param fit A `bayesbem_fit`, or a fit on several outputs.
#' @param baseline,retrofit [scenario()]s (or simulators) over the same
#'   periods.
#' @template args-ndraws-runs
#' @param discrepancy What the retrofit does to the discrepancy (see
#'   Details).
#' @template args-covariates-scenario
#' @template args-cache-dir
#' @template args-total
#' @param ... Unused.
#' @return A `bayesbem_savings`: a list with the draws-by-periods matrices
#'   `baseline`, `retrofit` and `savings`, `inputs`, `draw`, the scenarios
#'   and `discrepancy`. `summary(x, level)` gives per period and in total
#'   the means of baseline and retrofit, the savings' mean, sd and
#'   interval, and the savings as a share of the baseline. On several
#'   outputs, a `bayesbem_savings_outputs`: `outputs`, each output's
#'   `bayesbem_savings`, and `total`, the draws (by periods and their total)
#'   of the weighted total; its `summary()` stacks the outputs' savings and
#'   the total's with a first column `output`.
#' @family prediction
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' s <- savings(seb_fit, scenario(sim),
#'              scenario(sim, scale = c(equipment_power_density = 0.7)), ndraws = 20)
#' s
#' plot_savings(s)
#' }
savings <- function(fit, baseline, retrofit, ndraws = 40,
                    discrepancy = c("same", "proportional", "none"), covariates = NULL,
                    cache_dir = NULL, total = NULL, ...) {
  rlang::check_dots_empty()
  check_same_periods(as_scenario(baseline), as_scenario(retrofit))
  match_choice(discrepancy)
  check_fit(fit)
  UseMethod("savings")
}

#' @export
savings.bayesbem_fit <- function(fit, baseline, retrofit, ndraws = 40,
                                 discrepancy = c("same", "proportional", "none"),
                                 covariates = NULL, cache_dir = NULL, total = NULL, ...) {
  baseline <- as_scenario(baseline)
  retrofit <- as_scenario(retrofit)
  discrepancy <- match_choice(discrepancy)
  check_no_total(total)
  inputs <- scenario_inputs(fit, baseline, covariates)
  runs <- scenario_runs(fit, list(baseline, retrofit), ndraws, cache_dir)
  base <- runs$simulated[[1]]
  new <- runs$simulated[[2]]
  if (discrepancy != "none") {
    delta <- scenario_delta(fit, inputs, base, runs$draws)$delta
    new <- new + if (discrepancy == "same") delta else delta * (new / base)
    base <- base + delta
  }
  structure(list(baseline = base, retrofit = new, savings = base - new,
                 inputs = baseline$simulator$x, draw = runs$index,
                 scenarios = list(baseline = baseline, retrofit = retrofit),
                 discrepancy = discrepancy),
            class = "bayesbem_savings")
}

# savings() of a fit on several outputs: each output's from the same runs
# (shared_runs(), one run per draw and scenario for every output), and the
# weighted total of their savings draw by draw.
#' @export
savings.bayesbem_fit_outputs <- function(fit, baseline, retrofit, ndraws = 40,
                                         discrepancy = c("same", "proportional", "none"),
                                         covariates = NULL, cache_dir = NULL, total = NULL, ...) {
  call <- rlang::current_env()
  baseline <- as_scenario(baseline)
  retrofit <- as_scenario(retrofit)
  discrepancy <- match_choice(discrepancy)
  check_output_covariates(covariates, names(fit$outputs), call)
  per <- each_output_runs(fit, list(baseline, retrofit), function(k, fit, baseline, retrofit) {
    savings(fit, baseline, retrofit, ndraws = ndraws, discrepancy = discrepancy,
            covariates = covariates[[k]], cache_dir = cache_dir)
  }, call = call)
  saved <- if (!is.null(total)) {
    check_total_weights(total, lapply(per, `[[`, "inputs"), call = call)
    weighted_total(total, lapply(per, function(p) with_total(p$savings)),
                   lapply(per[names(total)], `[[`, "draw"))
  }
  structure(list(outputs = per, total = saved, weights = total,
                 scenarios = list(baseline = baseline, retrofit = retrofit)),
            class = "bayesbem_savings_outputs")
}

#' @export
summary.bayesbem_savings_outputs <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  cols <- c("period", "savings", "sd", "lower", "upper")
  tables <- lapply(object$outputs, function(s) summary(s, level = level)[cols])
  if (!is.null(object$total)) {
    tables$total <- data.frame(period = total_labels(ncol(object$total) - 1L),
                               savings = colMeans(object$total),
                               interval_table(object$total, level), row.names = NULL)
  }
  stack_outputs(tables)
}

#' @export
print.bayesbem_savings_outputs <- function(x, level = 0.9, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_savings_outputs}: {x$scenarios$retrofit$name} against {x$scenarios$baseline$name}",
            "* outputs {.val {names(x$outputs)}}{if (!is.null(x$total)) ' and their weighted total' else ''}",
            "")
  print_rounded(summary(x, level), 4)
  invisible(x)
}

#' @export
summary.bayesbem_savings <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  check_probability(level)
  saved <- with_total(object$savings)
  baseline <- colMeans(with_total(object$baseline))
  data.frame(period = total_labels(ncol(object$savings)), baseline = baseline,
             retrofit = colMeans(with_total(object$retrofit)), savings = colMeans(saved),
             interval_table(saved, level), percent = 100 * colMeans(saved) / baseline,
             row.names = NULL)
}

#' @export
print.bayesbem_savings <- function(x, level = 0.9, ...) {
  rlang::check_dots_empty()
  s <- summary(x, level)
  t <- s[nrow(s), ]
  assumption <- switch(x$discrepancy,
                       same = "unchanged by the retrofit (it cancels from the savings)",
                       proportional = "scaled with the simulated use",
                       none = "left out")
  cat_lines("{.cls bayesbem_savings}: {x$scenarios$retrofit$name} against {x$scenarios$baseline$name}",
            "* {x$scenarios$baseline$simulator$name}, {ncol(x$savings)} period{?s}, {nrow(x$savings)} paired posterior draw{?s}",
            "* discrepancy: {assumption}",
            "* total savings {signif(t$savings, 3)} ({round(100 * level)} % interval {signif(t$lower, 3)} to {signif(t$upper, 3)}), {round(t$percent, 1)} % of the baseline",
            "* Monte Carlo standard error of the total: {signif(t$sd / sqrt(nrow(x$savings)), 2)} (sd / sqrt(draws); more draws with {.arg ndraws} narrow it and steady the interval's ends)",
            "")
  print_rounded(s, 4)
  invisible(x)
}

# Baseline and retrofit must be over the same periods (the same weather).
check_same_periods <- function(baseline, retrofit, call = rlang::caller_env()) {
  a <- baseline$simulator$x
  b <- retrofit$simulator$x
  same <- nrow(a) == nrow(b) && identical(names(a), names(b)) &&
    isTRUE(all.equal(a, b, check.attributes = FALSE))
  if (!same) {
    abort_bayesbem(c("{.arg baseline} and {.arg retrofit} must cover the same periods under the same weather.",
                     x = "Their simulators have {nrow(a)} and {nrow(b)} period{?s}{if (nrow(a) == nrow(b)) ' with other observable inputs'}.",
                     i = "Make both simulators with the same weather file and periods ({.arg by})."),
                   "scenario", call = call)
  }
}

#' Avoided energy use: adjusted baseline less measured use (IPMVP Option D)
#'
#' After a retrofit, the savings of the reporting period are the avoided
#' energy use: the adjusted baseline, the calibrated pre-retrofit model
#' under the reporting period's weather ([predict_scenario()] with the
#' discrepancy and the observation noise: what the meter would have read),
#' less the measured use. Its uncertainty is the adjusted baseline's, draw
#' by draw.
#'
#' The fractional savings uncertainty (FSU) is the half-width of the
#' interval of the total over the total's size. Beside it, ASHRAE Guideline 14's
#' formula (Annex B; Reddy and Claridge 2000) for the same level:
#' `FSU = t * 1.26 * CV * sqrt((n / n') * (1 + 2 / n') / m) / F`, with `CV`
#' the calibrated model's CV(RMSE) on its `n` training periods (as a
#' fraction, `n - 1` degrees of freedom), `n' = n (1 - rho) / (1 + rho)` for
#' the lag-1 autocorrelation `rho` of the training residuals (`n` when
#' `rho <= 0`), `m` the reporting periods, `F` the savings as a fraction of
#' the adjusted baseline and `t` Student's quantile with `n - 1` degrees of
#' freedom. The formula's 1.26 was fitted to monthly data; its CV is
#' in-sample, so where the discrepancy fits the training bills closely it
#' understates the uncertainty of a prediction for another year.
#'
#' @param fit A `bayesbem_fit` of the pre-retrofit period.
#' @param reporting A [scenario()] (or simulator) of the reporting period:
#'   its weather, the pre-retrofit model.
#' @param obs Measured use in each reporting period (numeric, one per
#'   period of `reporting`; `NA` for a period without a measurement, e.g.
#'   the months after the last bill: such periods are left out of the
#'   table and the total); on several outputs, a list of them named by
#'   output.
#' @param discrepancy What the reporting period does to the discrepancy, as
#'   in [predict_scenario()].
#' @template args-ndraws-runs
#' @template args-level
#' @template args-covariates-scenario
#' @template args-cache-dir
#' @template args-total
#' @param ... Unused.
#' @return A `bayesbem_avoided_energy`: a list with `table` (per period and
#'   total: `adjusted_baseline`, `obs`, `avoided`, its `sd`, `lower`
#'   and `upper`), `fsu` (the Bayesian one and Guideline 14's), `draws` (the
#'   adjusted baseline's draws at the measured periods), `obs` and `level`.
#'   On several outputs, a `bayesbem_avoided_energy_outputs`: `outputs`,
#'   each output's result by output, and with `total` the draws of the
#'   weighted total of the outputs' totals; `summary()` stacks their
#'   tables with a first column `output`.
#' @family prediction
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem"))
#' after <- 0.8 * seb_field$y   # bills of a year after a retrofit
#' avoided_energy(seb_fit, sim, after, ndraws = 20)
#' }
avoided_energy <- function(fit, reporting, obs, ndraws = 40, level = 0.9,
                           discrepancy = c("same", "proportional", "none"), covariates = NULL,
                           cache_dir = NULL, total = NULL, ...) {
  rlang::check_dots_empty()
  check_fit(fit)
  as_scenario(reporting)
  check_probability(level)
  match_choice(discrepancy)
  UseMethod("avoided_energy")
}

#' @export
avoided_energy.bayesbem_fit <- function(fit, reporting, obs, ndraws = 40, level = 0.9,
                                        discrepancy = c("same", "proportional", "none"),
                                        covariates = NULL, cache_dir = NULL, total = NULL, ...) {
  reporting <- as_scenario(reporting)
  discrepancy <- match_choice(discrepancy)
  check_no_total(total)
  keep <- measured_periods(obs, nrow(reporting$simulator$x))
  obs <- obs[keep]
  m <- length(keep)
  prediction <- predict_scenario(fit, reporting, ndraws = ndraws, discrepancy = discrepancy,
                                 covariates = covariates, cache_dir = cache_dir)
  adjusted <- prediction$y[, keep, drop = FALSE]
  avoided <- adjusted - rep(obs, each = nrow(adjusted))
  both <- with_total(avoided)
  table <- data.frame(period = c(as.character(keep), "total"),
                      adjusted_baseline = colMeans(with_total(adjusted)),
                      obs = c(obs, sum(obs)), avoided = colMeans(both),
                      interval_table(both, level), row.names = NULL)
  total <- table[nrow(table), ]
  fsu <- data.frame(
    method = c("bayesbem (posterior draws)", "ASHRAE Guideline 14, Annex B"),
    fsu = c((total$upper - total$lower) / 2 / abs(total$avoided),
            guideline14_fsu(fit, m, abs(total$avoided) / total$adjusted_baseline, level))
  )
  structure(list(table = table, fsu = fsu, draws = adjusted, level = level,
                 scenario = reporting, obs = obs, draw = prediction$draw),
            class = "bayesbem_avoided_energy")
}

# avoided_energy() of a fit on several outputs: each output's from the same
# runs, `obs` a list by output, and the weighted total of the outputs'
# totals draw by draw (their measured periods may differ, so only the
# totals add up).
#' @export
avoided_energy.bayesbem_fit_outputs <- function(fit, reporting, obs, ndraws = 40, level = 0.9,
                                                discrepancy = c("same", "proportional", "none"),
                                                covariates = NULL, cache_dir = NULL, total = NULL,
                                                ...) {
  call <- rlang::current_env()
  reporting <- as_scenario(reporting)
  discrepancy <- match_choice(discrepancy)
  outputs <- names(fit$outputs)
  if (!is.list(obs) || is.null(names(obs)) || !setequal(names(obs), outputs)) {
    abort_bayesbem(c("On several outputs, {.arg obs} must be a list of measured uses named by output.",
                     x = "It is {describe_value(obs)}.",
                     i = "The outputs are {.val {outputs}}; e.g. {.code list({outputs[1]} = ..., {outputs[2]} = ...)}."),
                   "argument", call = call)
  }
  check_output_covariates(covariates, outputs, call)
  per <- each_output_runs(fit, list(reporting), function(k, fit, reporting) {
    avoided_energy(fit, reporting, obs[[k]], ndraws = ndraws, level = level,
                   discrepancy = discrepancy, covariates = covariates[[k]], cache_dir = cache_dir)
  }, call = call)
  avoided <- if (!is.null(total)) {
    check_total_weights(total, lapply(per, function(p) p$scenario$simulator$x), call = call)
    totals <- lapply(per, function(p) cbind(rowSums(p$draws) - sum(p$obs)))
    drop(weighted_total(total, totals, lapply(per, `[[`, "draw")))
  }
  structure(list(outputs = per, total = avoided, weights = total, level = level,
                 scenario = reporting),
            class = "bayesbem_avoided_energy_outputs")
}

#' @export
summary.bayesbem_avoided_energy_outputs <- function(object, ...) {
  rlang::check_dots_empty()
  cols <- c("period", "avoided", "sd", "lower", "upper")
  tables <- lapply(object$outputs, function(a) a$table[cols])
  if (!is.null(object$total)) {
    tables$total <- data.frame(period = "total", avoided = mean(object$total),
                               interval_table(cbind(object$total), object$level))
  }
  stack_outputs(tables)
}

#' @export
print.bayesbem_avoided_energy_outputs <- function(x, ...) {
  rlang::check_dots_empty()
  cat_lines("{.cls bayesbem_avoided_energy_outputs}: {x$scenario$simulator$name}",
            "* outputs {.val {names(x$outputs)}}{if (!is.null(x$total)) ' and their weighted total' else ''}, {round(100 * x$level)} % intervals",
            "")
  print_rounded(summary(x), 4)
  invisible(x)
}

# Guideline 14's fractional savings uncertainty (Annex B):
# t * 1.26 * CV * sqrt((n / n') (1 + 2 / n') / m) / F, CV and the lag-1
# autocorrelation from the calibrated model's training residuals.
guideline14_fsu <- function(fit, m, fraction, level) {
  obs <- fit$data$field[[fit$data$names$y]]
  pred <- colMeans(predict_draws(fit, field_inputs(fit$data))$y)
  n <- length(obs)
  cv <- cvrmse(obs, pred) / 100
  res <- obs - pred
  rho <- sum(res[-1] * res[-n]) / sum(res^2)
  n_eff <- if (rho > 0) n * (1 - rho) / (1 + rho) else n
  t <- stats::qt(interval_probs(level)[2], n - 1)
  t * 1.26 * cv * sqrt((n / n_eff) * (1 + 2 / n_eff) / m) / fraction
}

#' @export
print.bayesbem_avoided_energy <- function(x, ...) {
  rlang::check_dots_empty()
  t <- x$table[nrow(x$table), ]
  cat_lines("{.cls bayesbem_avoided_energy}: {x$scenario$simulator$name}",
            "* avoided energy use {signif(t$avoided, 3)} ({round(100 * x$level)} % interval {signif(t$lower, 3)} to {signif(t$upper, 3)}) over {nrow(x$table) - 1} measured period{?s} of {nrow(x$scenario$simulator$x)}",
            "* fractional savings uncertainty: {round(100 * x$fsu$fsu[1], 1)} % (Guideline 14's formula: {round(100 * x$fsu$fsu[2], 1)} %)",
            "")
  print_rounded(x$table, 4)
  invisible(x)
}
