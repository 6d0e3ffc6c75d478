# Predictions of a fit on several outputs: each output's from the same
# posterior draws, and their weighted totals.

# predict() of a fit on several outputs: each output's from the same
# posterior draws, and their weighted total (site energy, or cost with
# prices per unit of each output) draw by draw, so that the total's
# uncertainty holds the outputs' dependence through the shared parameters.
#' @export
predict.bayesbem_fit_outputs <- function(object, newdata = NULL, type = c("y", "eta", "delta"),
                                         ndraws = NULL, summary = TRUE, noise = FALSE,
                                         method = c("conditional", "sampled"),
                                         level = 0.9, total = NULL, ...) {
  rlang::check_dots_empty()
  type <- match_choice(type)
  check_bool(summary)
  check_bool(noise)
  if (match_choice(method) == "sampled") {
    abort_bayesbem("{.code method = \"sampled\"} is for a fit of one output calibrated with {.arg predict_at}.",
                   "argument")
  }
  inputs <- outputs_newdata(object, newdata)
  draws <- lapply(stats::setNames(names(inputs), names(inputs)), function(k) {
    predict_draws(object$outputs[[k]], inputs[[k]], ndraws = ndraws, noise = noise,
                  types = type)[[type]]
  })
  if (!is.null(total)) {
    check_total_weights(total, inputs)
    draws$total <- weighted_total(total, draws)
    inputs$total <- inputs[[names(total)[1]]]
  }
  if (!summary) {
    return(draws)
  }
  x <- object$data$names$x
  stack_outputs(Map(function(d, i) summarise_columns(d, i[x], level), draws, inputs[names(draws)]))
}

# The inputs at which each output is predicted, by output (see
# predict() of several outputs).
outputs_newdata <- function(fit, newdata, call = rlang::caller_env()) {
  outputs <- names(fit$outputs)
  if (is.null(newdata)) {
    return(lapply(fit$outputs, function(f) field_inputs(f$data)))
  }
  newdata <- as_numeric_table(newdata, "newdata", call = call)
  column <- fit$data$output
  if (!column %in% names(newdata)) {
    return(stats::setNames(rep(list(newdata), length(outputs)), outputs))
  }
  named <- unique(as.character(newdata[[column]]))
  unknown <- setdiff(named, outputs)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg newdata} names output{?s} {.val {unknown}}, not among the fit's.",
                     i = "The fit's outputs: {.val {outputs}}."),
                   "outputs", call = call)
  }
  lapply(stats::setNames(named, named), function(k) {
    newdata[as.character(newdata[[column]]) == k, setdiff(names(newdata), column), drop = FALSE]
  })
}

# Weights of a total: numbers named by predicted outputs, whose inputs agree.
check_total_weights <- function(total, inputs, call = rlang::caller_env()) {
  example <- sprintf("total = c(%s = 1)", names(inputs)[1])
  if (!is.numeric(total) || is.null(names(total)) || anyNA(total)) {
    abort_bayesbem(c("{.arg total} must be numbers named by output, not {describe_value(total)}.",
                     i = "For example {.code {example}}."),
                   "argument", call = call)
  }
  unknown <- setdiff(names(total), names(inputs))
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg total} names {.val {unknown}}, not among the outputs predicted.",
                     i = "The outputs predicted: {.val {names(inputs)}}."),
                   "argument", call = call)
  }
  same <- vapply(inputs[names(total)], function(d) {
    nrow(d) == nrow(inputs[[names(total)[1]]]) && isTRUE(all.equal(d, inputs[[names(total)[1]]],
                                                                   check.attributes = FALSE))
  }, logical(1))
  if (!all(same)) {
    abort_bayesbem(c("A total needs the same inputs for every output it adds.",
                     x = "{.val {names(total)[!same]}} {?is/are} predicted at other inputs than {.val {names(total)[1]}}.",
                     i = "Give {.arg newdata} without an output column: one set of inputs for all outputs."),
                   "argument", call = call)
  }
}
