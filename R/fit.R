#' Calibrate a simulator against field data (KOH model)
#'
#' Fits the Kennedy-O'Hagan model of Chong and Menberg (2018) with Stan's
#' NUTS sampler: a Gaussian-process emulator of the simulator over
#' `(x, t)`, a Gaussian-process discrepancy over `x`, and observation noise,
#' with the priors of [koh_priors()]. The Stan program is compiled when the
#' package is installed.
#'
#' @param field A [koh_data()] object, or the field data frame (then `sim` is
#'   required and columns are taken by position, see [koh_data()]).
#' @param sim The simulation data frame when `field` is a data frame.
#' @param priors A [koh_priors()] object.
#' @param chains,iter Number of Markov chains and iterations per chain
#'   (including warm-up).
#' @param warmup Warm-up iterations per chain; defaults to half of `iter`.
#' @param seed Random seed; by default one is drawn and stored in the result
#'   so the fit can be repeated.
#' @param cores Number of cores to run chains in parallel on.
#' @param control Sampler control passed to [rstan::sampling()]. The default
#'   `adapt_delta = 0.9` (Stan's is 0.8) takes smaller steps, which the
#'   curved posteriors of GP hyperparameters need to avoid divergences.
#' @param predict_at Optional data frame of observable inputs at which the
#'   calibrated output is sampled inside Stan as extra parameters (the
#'   paper's Appendix D; about twice as slow). Read them with
#'   `predict(fit, method = "sampled")`. [predict.koh_fit()] gives the same
#'   predictions by exact conditioning after the fit, for any inputs.
#' @param structure Which Stan program computes the likelihood: `"grid"`
#'   (`koh_grid.stan`) when every simulation run was made at every field
#'   input, as in the paper's workflow: the emulator covariance is then a
#'   Kronecker product and each gradient costs O(mt^3 + n^3) for mt runs and
#'   n field rows; `"dense"` (`koh.stan`) for any design, O((n + m)^3).
#'   Both give the same posterior. `"auto"` (the default) uses the grid
#'   program whenever the data allow it (see `koh_data()$grid`) and
#'   `predict_at` is not given.
#' @param covariates Optional data frame, one row per field row, whose
#'   columns enter the discrepancy as parametric terms (see [extend()], which
#'   is the usual way to add them).
#' @param ... Further arguments to [rstan::sampling()], e.g. `init` or
#'   `refresh`.
#' @return An object of class `koh_fit`: the `stanfit`, the [koh_data()]
#'   (with its scaling), the priors and the sampler settings. Use `print()`,
#'   `summary()` and [posterior::as_draws()] on it.
#' @family calibration
#' @export
#' @examples
#' \donttest{
#' fit <- calibrate(seb_field, seb_sim, chains = 1, iter = 300, seed = 1)
#' fit
#' }
calibrate <- function(field, sim = NULL, priors = koh_priors(), chains = 4L,
                      iter = 2000L, warmup = floor(iter / 2), seed = NULL,
                      cores = getOption("mc.cores", 1L),
                      control = list(adapt_delta = 0.9), predict_at = NULL,
                      structure = c("auto", "grid", "dense"), covariates = NULL, ...) {
  data <- as_koh_data(field, sim)
  data <- add_discrepancy_terms(data, covariates)
  if (!is.null(covariates) && !is.null(predict_at)) {
    abort_bayesbem(c("{.arg predict_at} cannot be combined with {.arg covariates}.",
                     i = "Predict after the fit with {.fn predict}, giving the covariates in {.arg newdata}."),
                   "argument")
  }
  check_priors(priors)
  check_count(chains)
  check_count(iter)
  check_count(cores)
  if (!isTRUE(checkmate::check_count(warmup)) || warmup >= iter) {
    abort_bayesbem(c("{.arg warmup} must be a whole number from 0 to {.arg iter} - 1 ({iter - 1}).",
                     x = "It is {.val {format(warmup)}}."),
                   "argument")
  }
  seed <- seed %||% sample.int(.Machine$integer.max, 1L)
  check_count(seed)
  structure <- choose_structure(data, match.arg(structure), predict_at)
  x_pred <- if (!is.null(predict_at)) scale_newdata(data, predict_at, "predict_at")
  stan_data <- koh_stan_data(data, priors, x_pred, structure)
  model <- if (structure == "grid") stanmodels$koh_grid else stanmodels$koh
  stanfit <- muffle_rstan_diagnostics(
    rstan::sampling(model, data = stan_data, chains = chains,
                    iter = iter, warmup = warmup, seed = seed,
                    cores = min(cores, chains), control = control, ...)
  )
  if (stanfit@mode != 0L) {
    abort_sampling_failure(data, priors$nugget, structure)
  }
  fit <- new_koh_fit(stanfit, data = data, priors = priors,
                     settings = list(chains = chains, iter = iter, warmup = warmup, seed = seed,
                                     structure = structure),
                     predict_at = if (!is.null(predict_at)) predict_at[data$names$x])
  check_convergence(fit)
  fit
}

# Stan stops when a Cholesky factor fails at every initial value; Stan only
# says "Matrix m is not positive definite". Name the matrix: the emulator's
# correlation factors are tried at long length scales (rho up to 0.999),
# where they are closest to singular.
abort_sampling_failure <- function(data, nugget, structure, call = rlang::caller_env()) {
  factors <- list("the correlation of the field inputs (K_x)" = data$xf)
  if (structure == "grid") {
    factors[["the correlation of the simulation runs (K_t)"]] <- data$grid$design
  } else {
    factors[["the correlation of the simulation rows"]] <- cbind(data$xc, data$tc)
  }
  singular <- names(factors)[vapply(factors, function(u) {
    pair <- pair_geometry(u, u)
    any(vapply(c(0.9, 0.99, 0.999), function(rho) {
      inherits(try(chol(jittered_cor(pair, rep(-4 * log(rho), ncol(u)), nugget)), silent = TRUE),
               "try-error")
    }, logical(1)))
  }, logical(1))]
  if (length(singular) == 0L) {
    abort_bayesbem(c("Stan could not sample the model.",
                     i = "Rerun with {.code refresh = 1} to see Stan's messages."),
                   "sampling", call = call)
  }
  abort_bayesbem(c("Stan could not sample the model: the Cholesky factor of {singular[1]} failed.",
                   x = "With {.code nugget = {nugget}} it is not positive definite at long length scales.",
                   i = "Raise {.arg nugget} in {.fn koh_priors} (e.g. {.code koh_priors(nugget = 1e-4)}), or drop nearly identical rows."),
                 "cholesky", call = call)
}

# rstan's own convergence warnings are unclassed; check_convergence() reports
# the same problems with a class and a hint, so those are muffled here.
muffle_rstan_diagnostics <- function(expr) {
  pattern <- paste("divergent transition|maximum treedepth|R-hat|Effective Samples Size",
                   "BFMI|pairs\\(\\) plot|chains have not mixed", sep = "|")
  withCallingHandlers(expr, warning = function(w) {
    if (grepl(pattern, conditionMessage(w))) invokeRestart("muffleWarning")
  })
}

new_koh_fit <- function(stanfit, data, priors, settings, predict_at = NULL) {
  structure(list(stanfit = stanfit, data = data, priors = priors, settings = settings,
                 predict_at = predict_at),
            class = "koh_fit")
}

#' Posterior draws of a KOH calibration in physical units
#'
#' The calibration parameters are named after their columns in the
#' simulation table and given in their physical units; the correlation
#' parameters `beta_eta[...]` and `beta_delta[...]` are labelled by input;
#' `lambda_eta`, `lambda_delta` and `lambda_e` are precisions on the
#' standardised output scale.
#'
#' @param x A `koh_fit`.
#' @param ... Unused.
#' @return A [posterior::draws_array].
#' @family calibration
#' @name as_draws.koh_fit
#' @examples
#' posterior::summarise_draws(posterior::as_draws(seb_fit))
NULL

#' @rdname as_draws.koh_fit
#' @exportS3Method posterior::as_draws_array
as_draws_array.koh_fit <- function(x, ...) {
  d <- x$data
  h_names <- names(d$covariates)
  arr <- as.array(x$stanfit, pars = c("tf", "beta_eta", "beta_delta", "lambda_eta",
                                      "lambda_delta", "lambda_e",
                                      if (length(h_names) > 0L) "gamma", "lp__"))
  tf <- grep("^tf\\[", dimnames(arr)[[3]])
  for (k in seq_along(tf)) {
    arr[, , tf[k]] <- arr[, , tf[k]] * (d$scaling$t_max[[k]] - d$scaling$t_min[[k]]) +
      d$scaling$t_min[[k]]
  }
  dimnames(arr)[[3]] <- c(d$names$t,
                          sprintf("beta_eta[%s]", c(d$names$x, d$names$t)),
                          sprintf("beta_delta[%s]", d$names$x),
                          "lambda_eta", "lambda_delta", "lambda_e",
                          sprintf("gamma[%s]", h_names), "lp__")
  # discrepancy-term coefficients in output units per covariate unit
  for (k in seq_along(h_names)) {
    j <- sprintf("gamma[%s]", h_names[k])
    arr[, , j] <- arr[, , j] * d$scaling$y_scale / d$h_scale[[k]]
  }
  posterior::as_draws_array(arr)
}

# Draws (rows) of calibration parameters `names` in physical units.
parameter_draws <- function(fit, names = fit$data$names$t) {
  posterior::as_draws_matrix(as_draws_array.koh_fit(fit))[, names, drop = FALSE]
}

#' @rdname as_draws.koh_fit
#' @exportS3Method posterior::as_draws
as_draws.koh_fit <- function(x, ...) as_draws_array.koh_fit(x, ...)

#' @rdname as_draws.koh_fit
#' @exportS3Method posterior::as_draws_df
as_draws_df.koh_fit <- function(x, ...) posterior::as_draws_df(as_draws_array.koh_fit(x))

#' Summarise a KOH calibration
#'
#' Posterior summaries of the calibration parameters in physical units and of
#' the Gaussian-process hyperparameters: mean, sd, 5%, 50% and 95%
#' quantiles, rank-normalised R-hat, bulk and tail effective sample sizes
#' (all from the posterior package).
#'
#' @param object,x A `koh_fit`, or for `print()` its summary.
#' @param ... Unused.
#' @return `summary()` returns an object of class `summary.koh_fit`: a list
#'   with data frames `parameters` and `hyperparameters`, and the sizes and
#'   sampler settings; `print()` returns its argument invisibly.
#' @family calibration
#' @export
#' @examples
#' summary(seb_fit)$parameters
#' seb_fit
summary.koh_fit <- function(object, ...) {
  s <- summarise_fit(
    object, mean = mean, sd = stats::sd,
    quantiles = function(v) {
      stats::setNames(stats::quantile(v, c(0.05, 0.5, 0.95), names = FALSE),
                      c("q5", "q50", "q95"))
    },
    rhat = posterior::rhat, ess_bulk = posterior::ess_bulk, ess_tail = posterior::ess_tail
  )
  is_tf <- s$variable %in% object$data$names$t
  structure(
    list(parameters = s[is_tf, , drop = FALSE],
         hyperparameters = s[!is_tf, , drop = FALSE],
         data = object$data[c("n", "m", "p", "q")],
         settings = object$settings,
         sampler = sampler_diagnostics(object$stanfit)),
    class = "summary.koh_fit"
  )
}

# posterior::summarise_draws() over every variable of a fit but lp__, with
# plain numeric columns (not posterior's pillar-formatted ones).
summarise_fit <- function(fit, ...) {
  draws <- as_draws_array.koh_fit(fit)
  draws <- posterior::subset_draws(draws, variable = setdiff(posterior::variables(draws), "lp__"))
  s <- withCallingHandlers(posterior::summarise_draws(draws, ...), warning = function(w) {
    # posterior notes each time that it caps a short run's ESS at S log10(S);
    # the capped (smaller) value is what is reported and tested, so muffle it
    if (grepl("ESS has been capped", conditionMessage(w), fixed = TRUE)) {
      invokeRestart("muffleWarning")
    }
  })
  as.data.frame(lapply(s, function(col) as.vector(unclass(col))))
}

#' @rdname summary.koh_fit
#' @param digits Significant digits to print.
#' @export
print.summary.koh_fit <- function(x, digits = 3, ...) {
  st <- x$settings
  cat(sprintf("KOH calibration: %d field rows, %d simulation rows, %d inputs, %d parameters (%s likelihood)\n",
              x$data$n, x$data$m, x$data$p, x$data$q, st$structure %||% "dense"))
  cat(sprintf("NUTS: %d chains x %d iterations (%d warm-up), seed %d; %d divergent transitions\n\n",
              st$chains, st$iter, st$warmup, st$seed, x$sampler$divergent))
  cat("Calibration parameters (physical units):\n")
  print_summary_table(x$parameters, digits)
  cat("\nGaussian-process hyperparameters (standardised scale):\n")
  print_summary_table(x$hyperparameters, digits)
  invisible(x)
}

print_summary_table <- function(s, digits) {
  out <- s[-1]
  rownames(out) <- s$variable
  num <- c("mean", "sd", "q5", "q50", "q95")
  out[num] <- lapply(out[num], signif, digits = digits)
  out$rhat <- round(out$rhat, 3)
  out[c("ess_bulk", "ess_tail")] <- lapply(out[c("ess_bulk", "ess_tail")], round)
  print(out)
}

#' @rdname summary.koh_fit
#' @export
print.koh_fit <- function(x, digits = 3, ...) {
  print(summary(x), digits = digits)
  invisible(x)
}
