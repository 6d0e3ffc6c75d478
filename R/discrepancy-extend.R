#' Extend a calibration with the effect the simulator misses
#'
#' Refits a `bayesbem_fit` with a named effect added, in one of two ways:
#' * statistically (`with`): each named covariate enters the discrepancy as
#'   a parametric term, `delta(x) + sum_k gamma_k w_k` (the mean functions
#'   `h(x)' gamma` of Kennedy and O'Hagan), with its own coefficient and a
#'   normal(0, `gamma_sd`) prior (see [koh_priors()]). A covariate can be an
#'   observable input the simulator treats wrongly or anything the modeller
#'   knows per field row (occupancy, working days, a step at a meter or
#'   equipment change date, ...). Covariates are divided by their range
#'   (largest minus smallest value) but not centred: the prior's strength
#'   is then the same in any units, and zero keeps its meaning ("no
#'   effect"). A covariate far from zero (working days, 20-23) therefore
#'   also shifts the output's level, like an intercept; subtract a
#'   meaningful origin first (e.g. `working_days - 20`) where that is not
#'   wanted. The coefficients are reported in output units per covariate unit as
#'   `gamma[<name>]` by [posterior::as_draws()];
#' * physically (`sim`): a new simulation table from a simulator that
#'   includes the mechanism, typically with a new calibration parameter.
#'
#' The other settings (priors, chains, iterations, seed, structure) are
#' those of `fit` unless given in `...`. The result is a `bayesbem_fit` like any
#' other: compare it with the original with [compare_fits()].
#'
#' @param fit A `bayesbem_fit`.
#' @param with Names of the covariates to add as discrepancy terms: columns
#'   of `covariates`, observable inputs of the fit, or regions of them as
#'   [explain_discrepancy()] names them ("temp > 11.8",
#'   a step: 1 above, 0 below, added as column `temp>11.8`; "occupancy,
#'   where temp > 14.9", a line in occupancy there and 0 elsewhere, added
#'   as two columns, the step `temp>14.9` and `occupancy:temp>14.9`,
#'   occupancy there; any threshold can be given), or hinges, "max(temp -
#'   18, 0)" (a load growing with temperature above 18, a cooling balance
#'   point) and "max(12 - temp, 0)" (growing as it falls below 12), added
#'   as `max(temp-18,0)`. [predict()] computes these columns from
#'   `newdata`'s own columns when it lacks them.
#' @param covariates A data frame with one row per field row (in the field
#'   data's order).
#' @param sim A new simulation table, in the layout of [koh_data()] (by
#'   position: `eta`, the fit's observable inputs, then the calibration
#'   parameters).
#' @param output On a fit on several outputs, the output whose discrepancy
#'   takes the terms of `with` (one of `names(fit$outputs)`); `sim` is
#'   then a long table of every output's runs.
#' @param ... Arguments of [calibrate()] that replace the fit's.
#' @return A `bayesbem_fit` (on several outputs, a fit on them all).
#' @family discrepancy
#' @export
#' @examples
#' \donttest{
#' working <- data.frame(working_days = c(22, 20, 21, 22, 22, 20, 23, 21, 21, 23, 20, 21))
#' ext <- extend(seb_fit, with = "working_days", covariates = working, refresh = 0)
#' posterior::summarise_draws(posterior::subset_draws(posterior::as_draws(ext),
#'                                                    variable = "gamma"))
#' }
extend <- function(fit, with = NULL, covariates = NULL, sim = NULL, output = NULL, ...) {
  if (is.null(with) == is.null(sim)) {
    abort_bayesbem(c("Give either {.arg with} (covariate names) or {.arg sim} (a new simulation table).",
                     i = "{.arg with} adds statistical discrepancy terms; {.arg sim} a simulator with the missing mechanism."),
                   "argument")
  }
  check_fit(fit)
  UseMethod("extend")
}

#' @export
extend.bayesbem_fit <- function(fit, with = NULL, covariates = NULL, sim = NULL, output = NULL,
                                ...) {
  if (!is.null(output)) {
    abort_bayesbem("{.arg output} is for fits on several outputs; this fit has one.", "argument")
  }
  data <- fit$data
  terms <- data$covariates
  if (!is.null(sim)) {
    # the parameters it shares with the fit keep their scales
    scales <- t_scales(data$scaling)
    data <- koh_data(field_table(data), sim, y = data$names$y,
                     scales = scales[intersect(names(scales), names(sim))])
  } else {
    terms <- extension_covariates(data, with, covariates)
  }
  refit(fit, field = data, covariates = terms, ...)
}

# extend() of a fit on several outputs: the terms of `with` on one output's
# discrepancy, or every output's runs from a new long table.
#' @export
extend.bayesbem_fit_outputs <- function(fit, with = NULL, covariates = NULL, sim = NULL,
                                        output = NULL, ...) {
  call <- rlang::current_env()
  terms <- fit_covariates(fit)
  if (!is.null(sim)) {
    field <- outputs_long_table(fit$data)
    scales <- t_scales(fit$data$scaling)
    data <- koh_data(field, sim, output = fit$data$output,
                     scales = scales[intersect(names(scales), names(sim))])
    return(refit(fit, field = data, covariates = terms, ...))
  }
  one <- output_fit(fit, output %||% abort_bayesbem(
    c("On a fit on several outputs, {.arg output} must say whose discrepancy takes the terms.",
      i = "The outputs: {.val {names(fit$outputs)}}."), "argument", call = call))
  name <- if (is.numeric(output)) names(fit$outputs)[output] else output
  terms[[name]] <- extension_covariates(one$data, with, covariates, call = call)
  refit(fit, covariates = terms, ...)
}

# The discrepancy terms of an extension: the fit's, plus `with` taken from
# `covariates` or the observable inputs.
extension_covariates <- function(data, with, covariates, call = rlang::caller_env()) {
  if (!is.character(with) || length(with) == 0L) {
    abort_bayesbem("{.arg with} must name one or more covariates.", "argument", call = call)
  }
  pool <- data$field[data$names$x]
  if (!is.null(covariates)) {
    covariates <- covariate_table(covariates, data$n, call = call)
    pool <- cbind(pool, covariates[setdiff(names(covariates), names(pool))])
  }
  for (name in setdiff(with, names(pool))) {
    columns <- term_columns(name, pool)
    if (is.null(columns)) next
    pool[names(columns)] <- columns
    with <- append(with[with != name], names(columns), after = match(name, with) - 1L)
  }
  with <- unique(with)
  unknown <- setdiff(with, names(pool))
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg with} names {.field {unknown}}, neither an observable input, a column of {.arg covariates} nor a region or hinge of them.",
                     i = "Available: {.field {names(pool)}}, and regions and hinges of them, e.g. {.val {names(pool)[1]} > 10}, {.val {names(pool)[2]}, where {names(pool)[1]} < 10} or {.val max({names(pool)[1]} - 10, 0)}."),
                   "columns", call = call)
  }
  old <- data$covariates
  added <- pool[, setdiff(with, names(old)), drop = FALSE]
  if (is.null(old)) added else cbind(old, added)
}
