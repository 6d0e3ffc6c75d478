# Fits on several outputs (meters). Stage 2 samples the shared calibration
# parameters with every output's discrepancy and noise at once
# (koh.stan's stage 2, koh_basis.stan: output k's rho_delta and beta_delta are
# its block of p elements, its lambda_delta, lambda_e and lambda_eta element
# k, its beta_eta and b its blocks, its gamma the columns of its own
# discrepancy terms). The fit names each output's variables once
# ("gas:lambda_e"), and each output's view (output_view()) is a one-output
# fit whose draws are the shared ones and the output's own: every tool that
# reads a one-output fit reads it, and the outputs' draws stay paired (draw
# i of every output is the same draw of tf).

# Output `k`'s view of a fit on several outputs: a one-output fit whose
# draws are the shared variables and the output's own, the prefix dropped
# (posterior's subset_draws()), with the output's data, its emulator and
# each chain's starting values reduced to its elements (`part`, its
# output_parts()).
output_view <- function(fit, k, emulator, part) {
  prefix <- paste0(k, ":")
  variables <- posterior::variables(fit$draws)
  keep <- startsWith(variables, prefix) | !grepl(":", variables, fixed = TRUE)
  draws <- posterior::subset_draws(fit$draws, variable = variables[keep])
  posterior::variables(draws) <- sub(prefix, "", posterior::variables(draws), fixed = TRUE)
  inits <- lapply(fit$inits, function(chain) {
    for (par in intersect(names(chain), names(part$elements))) {
      kept <- as.vector(chain[[par]])[part$elements[[par]]]
      chain[[par]] <- if (par %in% part$scalars) kept else as.array(kept)
    }
    chain
  })
  settings <- fit$settings
  settings$segments <- settings$segments[k]
  settings$shifts <- settings$shifts[k]
  new_bayesbem_fit(draws, fit$sampler, inits, fit$data$outputs[[k]], fit$priors, settings,
                   emulator = emulator)
}

# A fit on several outputs with each output's view, by name: class
# `bayesbem_fit_outputs`, whose methods of the package's verbs apply the
# one-output verb to each view.
with_output_views <- function(fit) {
  emulators <- output_emulators(fit$data, fit$emulator)
  parts <- output_parts(fit$data, fit$emulator)
  k <- names(fit$data$outputs)
  fit$outputs <- stats::setNames(Map(function(k, em, part) output_view(fit, k, em, part),
                                     k, emulators, parts[k]), k)
  class(fit) <- c("bayesbem_fit_outputs", class(fit))
  fit
}

# A tool's result for each output of a fit on several outputs, by output,
# and their tables stacked with a first column `output`. Data other than
# the fit's own (held-out periods, simulators) are an output's own, so a
# tool given any (`given`, its arguments by name) says to go output by
# output.
output_results <- function(fit, tool, given, ..., call = rlang::caller_env()) {
  given <- Filter(Negate(is.null), given)
  if (length(given) > 0L) {
    fn <- rlang::as_label(rlang::enexpr(tool))
    abort_bayesbem(c("On a fit on several outputs, {.arg {names(given)}} belong{?s/} to one output.",
                     i = "Give such data output by output, to an output's view: {.code {fn}(output_fit(fit, \"{names(fit$outputs)[1]}\"), ...)}."),
                   "argument", call = call)
  }
  results <- lapply(fit$outputs, tool, ...)
  list(results = results, table = stack_outputs(results))
}

# A verb's one-output method given `total`, which adds a fit's outputs.
check_no_total <- function(total, call = rlang::caller_env()) {
  if (!is.null(total)) {
    abort_bayesbem("{.arg total} adds the outputs of a fit on several outputs; this fit has one.",
                   "argument", call = call)
  }
}

# A tool of one meter given a fit on several outputs.
check_one_output <- function(fit, call = rlang::caller_env()) {
  if (inherits(fit, "bayesbem_fit_outputs")) {
    abort_bayesbem(c("{.arg fit} has several outputs; this tool takes one at a time.",
                     i = "Give {.code output_fit(fit, \"{names(fit$outputs)[1]}\")} and that meter's data."),
                   "argument", call = call)
  }
}

# The one-output fits of a fit: its outputs' views, or the fit itself.
output_fit_list <- function(fit) {
  if (inherits(fit, "bayesbem_fit_outputs")) fit$outputs else list(fit)
}

#' One output of a fit on several outputs
#'
#' A fit on several outputs (meters) calibrates the parameters they share
#' with every output's data at once. Each output is also a fit of its own:
#' its data, its emulator, its discrepancy and noise, and the shared draws
#' of the calibration parameters (draw `i` of every output is the same draw
#' of the parameters). Every tool that takes a fit takes it: [predict()],
#' [discrepancy()], [explain_discrepancy()], [validate_emulator()],
#' [identifiability()], the plots.
#'
#' @param fit A fit on several outputs ([calibrate()] on data with an
#'   `output` column, see [koh_data()]).
#' @param output The output's name (or number).
#' @return A `bayesbem_fit` of the one output.
#' @family calibration
#' @export
#' @examples
#' \donttest{
#' # electricity and gas of the embedded model, 12 months of 2013
#' epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
#' sim <- bem_simulator(epw, output = c("electricity", "gas"))
#' pars <- bem_parameters()
#' pars <- pars[pars$parameter %in% c("infiltration_per_exterior_area",
#'                                     "equipment_power_density"), ]
#' runs <- simulate_design(sim, design_lhs(pars, 12, seed = 1))
#' truth <- list(infiltration_per_exterior_area = 8e-4, equipment_power_density = 15)
#' field <- simulate_field(sim, truth, noise_sd = 20, seed = 2)
#' fit <- calibrate(field, runs, chains = 2, iter = 600, seed = 3)
#' fit
#' output_fit(fit, "gas")
#' }
output_fit <- function(fit, output) {
  if (!inherits(fit, "bayesbem_fit_outputs")) {
    abort_bayesbem(c("{.arg fit} must be a fit on several outputs, not {.obj_type_friendly {fit}}.",
                     i = "Calibrate on data with an {.field output} column (see {.fn koh_data})."),
                   "argument")
  }
  names <- names(fit$outputs)
  ok <- (rlang::is_string(output) && output %in% names) ||
    (rlang::is_scalar_integerish(output) && output >= 1 && output <= length(names))
  if (!ok) {
    abort_bayesbem(c("{.arg output} must name one of the fit's outputs, not {describe_value(output)}.",
                     i = "Its outputs: {.val {names}}."),
                   "argument")
  }
  fit$outputs[[output]]
}

# calibrate() on several outputs: the modular fit on grid designs, without
# predict_at.
check_outputs_path <- function(structure, modular, predict_at, call = rlang::caller_env()) {
  if (identical(modular, FALSE) || structure == "dense" || !is.null(predict_at)) {
    abort_bayesbem(c("A fit on several outputs is modular, on grid designs.",
                     x = "{.code modular = FALSE}, {.code structure = \"dense\"} and {.arg predict_at} are for one output.",
                     i = "Leave them at their defaults, and predict after the fit with {.fn predict}."),
                   "argument", call = call)
  }
}

# The field rows of a data set's largest output (its only one's), which
# sets the cost of a gradient and the sampler's defaults.
largest_output <- function(data) {
  max(vapply(output_data(data), `[[`, integer(1), "n"))
}

# Discrepancy terms of a fit on several outputs: `covariates` a list of
# tables named by output (those not named have none).
add_output_terms <- function(data, covariates, call = rlang::caller_env()) {
  check_output_covariates(covariates, names(data$outputs), call)
  for (k in names(data$outputs)) {
    data$outputs[[k]] <- add_discrepancy_terms(data$outputs[[k]], covariates[[k]], call = call)
  }
  data
}

# Covariates on several outputs: NULL, or a list of tables named by output
# (those not named have none).
check_output_covariates <- function(covariates, outputs, call = rlang::caller_env()) {
  if (is.null(covariates)) {
    return(invisible())
  }
  if (!is.list(covariates) || is.data.frame(covariates) || is.null(names(covariates)) ||
      length(setdiff(names(covariates), outputs)) > 0L) {
    abort_bayesbem(c("On several outputs, {.arg covariates} must be a list of tables named by output.",
                     i = "The outputs are {.val {outputs}}; e.g. {.code list({outputs[1]} = covariates)}."),
                   "covariates", call = call)
  }
}

# Which of output k's variables a table of several outputs shows, and under
# which names (the result's values; its names, the variables): the
# `shared` ones (calibration parameters) once, from the first output, each
# output's own prefixed by its name ("gas:lambda_e").
output_variables <- function(variables, k, outputs, shared) {
  keep <- if (k == outputs[1]) variables else setdiff(variables, shared)
  stats::setNames(ifelse(keep %in% shared, keep, paste0(k, ":", keep)), keep)
}
