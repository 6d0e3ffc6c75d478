# Fits on several outputs (meters). Stage 2 samples the shared calibration
# parameters with every output's discrepancy and noise at once
# (koh_modular.stan, koh_basis.stan: output k's rho_delta and beta_delta are
# its block of p elements, its lambda_delta, lambda_e and lambda_eta element
# k, its beta_eta and b its blocks, its gamma the columns of its own
# discrepancy terms). Each output is then also a one-output bayesbem_fit of
# its own, whose stanfit holds the shared draws of tf and that output's
# other parameters under the one-output names: every tool that reads a
# one-output fit reads it, and the outputs' draws stay paired (draw i of
# every output is the same draw of tf).

# The elements of output k among a K-output program's parameters, and the
# parameters that are one number per output (scalars in a one-output fit).
output_elements <- function(k, p, q, n_b, n_h) {
  block <- function(size) (k - 1L) * size + seq_len(size)
  list(elements = list(rho_delta = block(p), beta_delta = block(p), beta_eta = block(p + q),
                       b = block(n_b), lambda_delta = k, lambda_e = k, lambda_eta = k,
                       gamma = sum(n_h[seq_len(k - 1L)]) + seq_len(n_h[k])),
       scalars = c("lambda_delta", "lambda_e", "lambda_eta"))
}

# The stanfit `sf` reduced to some elements of its parameters (`elements`, a
# list by parameter; a parameter not named keeps all of its), renamed as a
# one-output program names them: element j of those kept is `par[j]`, and a
# parameter in `scalars` is `par`; the chains' starting values likewise.
# The sampler's diagnostics and settings are kept as they are.
output_stanfit <- function(sf, elements, scalars) {
  old <- new <- character()
  dims <- list()
  for (par in sf@model_pars) {
    dim <- sf@par_dims[[par]]
    if (length(dim) == 0L) {
      old <- c(old, par)
      new <- c(new, par)
      dims[[par]] <- integer(0)
      next
    }
    keep <- elements[[par]] %||% seq_len(prod(dim))
    scalar <- par %in% scalars
    old <- c(old, sprintf("%s[%d]", par, keep))
    new <- c(new, if (scalar) par else sprintf("%s[%d]", par, seq_along(keep)))
    dims[[par]] <- if (scalar) integer(0) else length(keep)
  }
  sf@sim$samples <- lapply(sf@sim$samples, function(chain) {
    kept <- stats::setNames(chain[old], new)
    attrs <- attributes(chain)
    attrs <- attrs[setdiff(names(attrs), c("names", "mean_pars", "inits"))]
    attributes(kept) <- c(attributes(kept), attrs)
    kept
  })
  sf@sim$fnames_oi <- new
  sf@sim$n_flatnames <- length(new)
  sf@sim$pars_oi <- sf@model_pars
  sf@sim$dims_oi <- dims[sf@model_pars]
  sf@par_dims <- dims[sf@model_pars]
  sf@inits <- lapply(sf@inits, function(chain) {
    for (par in intersect(names(chain), names(elements))) {
      kept <- as.vector(chain[[par]])[elements[[par]]]
      chain[[par]] <- if (par %in% scalars) kept else as.array(kept)
    }
    chain
  })
  sf
}

# The one-output fits of a stage-2 stanfit on `data` (one output or
# several), each built by `build(stanfit, data, emulator)`.
output_fits <- function(stanfit, data, emulator, build) {
  outputs <- output_data(data)
  emulators <- output_emulators(data, emulator)
  n_h <- vapply(outputs, function(d) ncol(discrepancy_design(d)), integer(1))
  first <- outputs[[1]]
  lapply(seq_along(outputs), function(k) {
    n_b <- length(emulators[[k]]$b)
    parts <- output_elements(k, first$p, first$q, n_b, n_h)
    build(output_stanfit(stanfit, parts$elements, parts$scalars), outputs[[k]], emulators[[k]])
  })
}

# A fit on several outputs: the stage-2 stanfit with every output's
# parameters, the bayesbem_outputs data, and `outputs`, each output's
# one-output fit (output_fits()) by name.
new_outputs_fit <- function(stanfit, data, fits, priors, settings) {
  structure(list(stanfit = stanfit, data = data, outputs = stats::setNames(fits, names(data$outputs)),
                 priors = priors, settings = settings),
            class = "bayesbem_outputs_fit")
}

# The one-output fits of a fit: its outputs', or the fit itself.
output_fit_list <- function(fit) {
  if (inherits(fit, "bayesbem_outputs_fit")) fit$outputs else list(fit)
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
  if (!inherits(fit, "bayesbem_outputs_fit")) {
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
  if (!is.null(covariates)) {
    unknown <- setdiff(names(covariates), names(data$outputs))
    if (!is.list(covariates) || is.data.frame(covariates) || is.null(names(covariates)) ||
        length(unknown) > 0L) {
      abort_bayesbem(c("On several outputs, {.arg covariates} must be a list of tables named by output.",
                       i = "The outputs are {.val {names(data$outputs)}}; e.g. {.code list({names(data$outputs)[1]} = covariates)}."),
                     "covariates", call = call)
    }
  }
  for (k in names(data$outputs)) {
    data$outputs[[k]] <- add_discrepancy_terms(data$outputs[[k]], covariates[[k]], call = call)
  }
  data
}

# Which of output k's variables a table of several outputs shows, and under
# which names (the result's values; its names, the variables): the
# `shared` ones (calibration parameters) once, from the first output, each
# output's own prefixed by its name ("gas:lambda_e").
output_variables <- function(variables, k, outputs, shared) {
  keep <- if (k == outputs[1]) variables else setdiff(variables, shared)
  stats::setNames(ifelse(keep %in% shared, keep, paste0(k, ":", keep)), keep)
}

#' @rdname output_fit
#' @param x A fit on several outputs.
#' @param ... Unused.
#' @exportS3Method posterior::as_draws_array
as_draws_array.bayesbem_outputs_fit <- function(x, ...) {
  rlang::check_dots_empty()
  draws <- lapply(names(x$outputs), function(k) {
    d <- as_draws_array.bayesbem_fit(x$outputs[[k]])
    v <- output_variables(posterior::variables(d), k, names(x$outputs), c(x$data$names$t, "lp__"))
    d <- posterior::subset_draws(d, variable = names(v))
    posterior::variables(d) <- unname(v)
    d
  })
  do.call(posterior::bind_draws, c(draws, along = "variable"))
}

#' @rdname output_fit
#' @exportS3Method posterior::as_draws
as_draws.bayesbem_outputs_fit <- function(x, ...) as_draws_array.bayesbem_outputs_fit(x, ...)

#' @export
summary.bayesbem_outputs_fit <- function(object, ...) {
  rlang::check_dots_empty()
  outputs <- lapply(object$outputs, summary)
  structure(list(parameters = outputs[[1]]$parameters, outputs = outputs,
                 settings = object$settings, sampler = fit_sampler_diagnostics(object)),
            class = "summary.bayesbem_outputs_fit")
}

#' @export
print.summary.bayesbem_outputs_fit <- function(x, ...) {
  rlang::check_dots_empty()
  st <- x$settings
  sizes <- vapply(x$outputs, function(s) s$data$n, integer(1))
  cat(sprintf("KOH calibration on %d outputs (%s field rows), %d parameters (modular%s)\n",
              length(sizes), paste(sprintf("%s %d", names(sizes), sizes), collapse = ", "),
              x$outputs[[1]]$data$q, if (identical(st$emulator, "basis")) ", basis emulators" else ""))
  cat(sprintf("NUTS: %d chains x %d iterations (%d warm-up), seed %d; %d divergent transitions%s\n\n",
              st$chains, st$iter, st$warmup, st$seed, x$sampler$divergent,
              minor_modes_label(st$dropped, st$restarted, st$kept_moved)))
  cat("Calibration parameters (physical units), shared by the outputs:\n")
  print_summary_table(x$parameters)
  for (k in names(x$outputs)) {
    cat(sprintf("\n%s: discrepancy and noise (standardised scale):\n", k))
    print_summary_table(x$outputs[[k]]$hyperparameters)
  }
  invisible(x)
}

#' @export
print.bayesbem_outputs_fit <- function(x, ...) {
  rlang::check_dots_empty()
  print(summary(x))
  invisible(x)
}
