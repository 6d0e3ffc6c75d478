# The bayesbem_fit object: its constructor, draws in the posterior package's
# formats, the summary and the print methods.

#' Posterior draws of a KOH calibration in physical units
#'
#' The calibration parameters are named after their columns in the
#' simulation table and given in their physical units; the correlation
#' parameters `beta_eta[...]` and `beta_delta[...]` are labelled by input;
#' `lambda_eta`, `lambda_delta` and `lambda_e` are precisions on the
#' standardised output scale; `phi` (with `noise_correlation = "ar1"`) is
#' the noise's AR(1) coefficient; `lambda_shift` (with `noise_shift =
#' "month"`) the precision of the months' shifts; `b[...]` are the coefficients of the emulator
#' mean (see [koh_priors()]) on the standardised output scale per unit of
#' the scaled \[0, 1\] inputs.
#'
#' @param x A `bayesbem_fit`.
#' @param ... Unused.
#' @return A [posterior::draws_array].
#' @family calibration
#' @name as_draws.bayesbem_fit
#' @examples
#' posterior::summarise_draws(posterior::as_draws(seb_fit))
NULL

#' @rdname as_draws.bayesbem_fit
#' @exportS3Method posterior::as_draws_array
as_draws_array.bayesbem_fit <- function(x, ...) {
  rlang::check_dots_empty()
  d <- x$data
  h_names <- names(d$covariates)
  b_names <- mean_term_names(x$priors, d)
  phi <- c(if (is_ar1(x$settings)) "phi", if (has_shifts(x$settings)) "lambda_shift")
  arr <- unclass(posterior::subset_draws(
    x$draws, variable = c("tf", "beta_eta", "beta_delta", "lambda_eta", "lambda_delta",
                          "lambda_e", phi, if (length(h_names) > 0L) "gamma",
                          if (length(b_names) > 0L) "b", "lp__")))
  tf <- grep("^tf\\[", dimnames(arr)[[3]])
  for (k in seq_along(tf)) arr[, , tf[k]] <- unscale_t1(arr[, , tf[k]], d$scaling, k)
  dimnames(arr)[[3]] <- c(d$names$t, emulator_draw_names(d)$beta_eta,
                          sprintf("beta_delta[%s]", d$names$x),
                          "lambda_eta", "lambda_delta", "lambda_e", phi,
                          sprintf("gamma[%s]", h_names), emulator_draw_names(d, b_names)$b, "lp__")
  # discrepancy-term coefficients in output units per covariate unit
  for (k in seq_along(h_names)) {
    j <- sprintf("gamma[%s]", h_names[k])
    arr[, , j] <- arr[, , j] * d$scaling$y_scale / d$h_scale[[k]]
  }
  posterior::as_draws_array(arr)
}

#' @rdname as_draws.bayesbem_fit
#' @exportS3Method posterior::as_draws
as_draws.bayesbem_fit <- function(x, ...) posterior::as_draws_array(x, ...)

#' @rdname as_draws.bayesbem_fit
#' @exportS3Method posterior::as_draws_df
as_draws_df.bayesbem_fit <- function(x, ...) posterior::as_draws_df(posterior::as_draws_array(x, ...))

#' Summarise a KOH calibration
#'
#' Posterior summaries of the calibration parameters in physical units and of
#' the Gaussian-process hyperparameters: mean, sd, 5%, 50% and 95%
#' quantiles, rank-normalised R-hat, bulk and tail effective sample sizes
#' (all from the posterior package).
#'
#' @param object,x A `bayesbem_fit`, or for `print()` its summary.
#' @param ... Unused.
#' @return `summary()` returns an object of class `summary.bayesbem_fit`: a list
#'   with data frames `parameters` and `hyperparameters` (row names: the
#'   variables), for a modular fit `emulator` (the emulator's
#'   hyperparameters, fixed at their stage-1 mode: column `value`) and
#'   `searches` (the log density each stage-1 search reached), for a fit
#'   calibrated with the basis emulator `basis` (the number of
#'   `components`, the `variance` they hold, the white variance `s2r` of the
#'   rest; else `NULL`), and
#'   the sizes and sampler settings; `print()` shows each row to two
#'   significant digits of its sd and returns its argument invisibly.
#' @family calibration
#' @export
#' @examples
#' summary(seb_fit)$parameters
#' seb_fit
summary.bayesbem_fit <- function(object, ...) {
  rlang::check_dots_empty()
  s <- summarise_fit(
    object, mean = mean, sd = stats::sd,
    quantiles = function(v) {
      stats::setNames(stats::quantile(v, c(0.05, 0.5, 0.95), names = FALSE),
                      c("q5", "q50", "q95"))
    },
    rhat = posterior::rhat, ess_bulk = posterior::ess_bulk, ess_tail = posterior::ess_tail
  )
  is_tf <- s$variable %in% object$data$names$t
  fixed <- s$variable %in% fixed_variables(object)
  rownames(s) <- s$variable
  structure(
    list(parameters = s[is_tf, , drop = FALSE],
         hyperparameters = s[!is_tf & !fixed, , drop = FALSE],
         emulator = if (any(fixed)) data.frame(value = s$mean[fixed], row.names = s$variable[fixed]),
         searches = object$emulator$searches,
         basis = basis_summary(object$emulator$basis),
         data = object$data[c("n", "m", "p", "q")],
         settings = object$settings,
         sampler = fit_sampler_diagnostics(object)),
    class = "summary.bayesbem_fit"
  )
}

# The basis emulator in a summary: its size, the variance its components
# hold and the white variance of the rest; NULL without one.
basis_summary <- function(basis) {
  if (is.null(basis)) {
    return(NULL)
  }
  list(components = length(basis$components), variance = basis$variance, s2r = basis$s2r)
}

# posterior::summarise_draws() over every variable of a fit but lp__, with
# plain numeric columns (not posterior's pillar-formatted ones). A modular
# fit's emulator hyperparameters are constant (its stage-1 mode): sd 0,
# R-hat and ESS NA.
summarise_fit <- function(fit, ...) {
  draws <- as_draws_array.bayesbem_fit(fit)
  draws <- posterior::subset_draws(draws, variable = setdiff(posterior::variables(draws), "lp__"))
  summarise_quietly(draws, list(...))
}

# posterior::summarise_draws(draws, <measures>) as a plain data frame.
summarise_quietly <- function(draws, measures) {
  s <- withCallingHandlers(do.call(posterior::summarise_draws, c(list(draws), measures)),
                           warning = function(w) {
    # posterior notes each time that it caps a short run's ESS at S log10(S);
    # the capped (smaller) value is what is reported and tested, so muffle it
    if (grepl("ESS has been capped", conditionMessage(w), fixed = TRUE)) {
      invokeRestart("muffleWarning")
    }
  })
  as.data.frame(lapply(s, function(col) as.vector(unclass(col))))
}

#' @rdname summary.bayesbem_fit
#' @export
print.summary.bayesbem_fit <- function(x, ...) {
  rlang::check_dots_empty()
  st <- x$settings
  cat(sprintf("KOH calibration: %d field rows, %d simulation rows, %d inputs, %d parameters (%s likelihood%s)\n",
              x$data$n, x$data$m, x$data$p, x$data$q, st$structure %||% "dense",
              paste0(if (identical(st$emulator, "basis")) ", modular, basis emulator" else
                       if (isTRUE(st$modular)) ", modular" else "",
                     if (identical(st$discrepancy_kernel, "additive")) ", additive discrepancy",
                     if (is_ar1(st)) ", AR(1) noise",
                     if (has_shifts(st)) ", a shift per month")))
  cat(sprintf("NUTS: %d chains x %d iterations (%d warm-up), seed %d; %d divergent transitions%s\n\n",
              st$chains, st$iter, st$warmup, st$seed, x$sampler$divergent,
              minor_modes_label(st$dropped, st$restarted, st$kept_moved)))
  cat("Calibration parameters (physical units):\n")
  print_summary_table(x$parameters)
  cat(sprintf("\nGaussian-process hyperparameters%s (standardised scale):\n",
              if (is_ar1(st)) " and the noise's AR(1) phi" else ""))
  print_summary_table(x$hyperparameters)
  if (!is.null(x$emulator)) {
    cat(sprintf("\nEmulator (standardised scale), fixed at its posterior mode given the runs (stage 1, %s):\n",
                emulator_searches_label(x$searches)))
    print(data.frame(value = signif(x$emulator$value, 3), row.names = rownames(x$emulator)))
  }
  if (!is.null(x$basis)) {
    cat(sprintf("\nStage 2 calibrated with a basis emulator: %d component%s holding %s%% of the runs' variance about their mean, the rest white (sd %s, standardised scale).\n",
                x$basis$components, if (x$basis$components > 1L) "s" else "", format(100 * x$basis$variance),
                format(signif(sqrt(x$basis$s2r), 3))))
  }
  invisible(x)
}

# Prints a summary table with one row per variable (the row names). Each
# row's mean, sd and quantiles get the decimals that show two significant
# digits of its sd (units differ between rows: 0.64, 12.3, 0.00135), without
# scientific notation; R-hat with 3 decimals, ESS as whole numbers.
print_summary_table <- function(s) {
  decimals <- sd_decimals(s$sd)
  out <- data.frame(row.names = s$variable)
  for (col in c("mean", "sd", "q5", "q50", "q95")) {
    out[[col]] <- vapply(seq_along(decimals), function(i) {
      formatC(s[[col]][i], format = "f", digits = decimals[i])
    }, character(1))
  }
  out$rhat <- formatC(s$rhat, format = "f", digits = 3)
  out$ess_bulk <- formatC(round(s$ess_bulk), format = "d")
  out$ess_tail <- formatC(round(s$ess_tail), format = "d")
  print(out, right = TRUE)
}

# Decimals that show two significant digits of each sd (at most 10; 3 where
# the sd is zero or not finite).
sd_decimals <- function(sd) {
  d <- 2 - ceiling(log10(sd) + 1e-12)
  d[!is.finite(d)] <- 3
  as.integer(pmin(pmax(d, 0), 10))
}

#' @rdname summary.bayesbem_fit
#' @export
print.bayesbem_fit <- function(x, ...) {
  rlang::check_dots_empty()
  print(summary(x))
  invisible(x)
}

# Draws (rows) of calibration parameters `names` in physical units.
parameter_draws <- function(fit, names = fit$data$names$t) {
  posterior::as_draws_matrix(posterior::as_draws_array(fit))[, names, drop = FALSE]
}

# as_draws_array() of a fit on several outputs: the shared parameters once,
# each output's own named "<output>:<variable>" (output_variables()).
#' @exportS3Method posterior::as_draws_array
as_draws_array.bayesbem_fit_outputs <- function(x, ...) {
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


# summary() of a fit on several outputs: the shared parameters once, each
# output's summary.
#' @export
summary.bayesbem_fit_outputs <- function(object, ...) {
  rlang::check_dots_empty()
  outputs <- lapply(object$outputs, summary)
  structure(list(parameters = outputs[[1]]$parameters, outputs = outputs,
                 settings = object$settings, sampler = fit_sampler_diagnostics(object)),
            class = c("summary.bayesbem_fit_outputs", "summary.bayesbem_fit"))
}

#' @export
print.summary.bayesbem_fit_outputs <- function(x, ...) {
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
