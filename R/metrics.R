#' ASHRAE Guideline 14 goodness-of-fit metrics
#'
#' `cvrmse()` is the coefficient of variation of the root mean squared error
#' and `nmbe()` the normalised mean bias error, both in percent, with `n - 1`
#' in the denominator as in ASHRAE Guideline 14 (and Chong & Menberg 2018):
#'
#' `CVRMSE = 100 * sqrt(sum((pred - obs)^2) / (n - 1)) / mean(obs)`
#'
#' `NMBE = 100 * sum(pred - obs) / ((n - 1) * mean(obs))`
#'
#' A positive NMBE means the predictions are too high on average.
#'
#' @param obs Observed values.
#' @param pred Predicted values, the same length as `obs`.
#' @return One number, in percent.
#' @family metrics
#' @export
#' @examples
#' obs <- c(100, 110, 120)
#' cvrmse(obs, c(101, 108, 123))
#' nmbe(obs, c(101, 108, 123))
cvrmse <- function(obs, pred) {
  check_metric_input(obs, pred)
  100 * sqrt(sum((pred - obs)^2) / (length(obs) - 1)) / mean(obs)
}

#' @rdname cvrmse
#' @export
nmbe <- function(obs, pred) {
  check_metric_input(obs, pred)
  100 * sum(pred - obs) / ((length(obs) - 1) * mean(obs))
}

check_metric_input <- function(obs, pred, call = rlang::caller_env()) {
  if (!is.numeric(obs) || !is.numeric(pred) || length(obs) != length(pred) ||
      length(obs) < 2L || anyNA(obs) || anyNA(pred)) {
    abort_bayesbem(c("{.arg obs} and {.arg pred} must be numeric vectors of the same length (at least 2), without missing values.",
                     x = "They have lengths {length(obs)} and {length(pred)}."),
                   "argument", call = call)
  }
}

# calibration_metrics() on the training data and, unless NULL, on `holdout`
# (a data frame with the output column and the observable inputs).
holdout_metrics <- function(fit, holdout, ndraws) {
  obs <- if (!is.null(holdout)) holdout[[fit$data$names$y]]
  calibration_metrics(fit, newdata = holdout, obs = obs, ndraws = ndraws)
}

# Held-out data need the output column and the observable inputs (checked
# before any fit starts; values are checked where they are scaled).
check_holdout <- function(holdout, data, call = rlang::caller_env()) {
  needed <- c(data$names$y, data$names$x)
  if (!is.data.frame(holdout) || !all(needed %in% names(holdout))) {
    abort_bayesbem(c("{.arg holdout} must be a data frame with the output and the observable inputs, {.field {needed}}.",
                     i = "Give the held-out outputs with their observable inputs (and covariates)."),
                   "columns", call = call)
  }
  invisible(holdout)
}

#' Calibration metrics of a KOH fit, with the Guideline 14 verdict
#'
#' Compares the calibrated predictions (posterior mean of `eta + delta`)
#' with the measured data: the training data, and held-out data when given.
#' ASHRAE Guideline 14 calls a model calibrated at CVRMSE <= 15% and
#' |NMBE| <= 5% for monthly data, and 30% and 10% for hourly data.
#'
#' @param fit A `koh_fit`.
#' @param newdata Held-out observable inputs (a data frame with the field
#'   inputs' columns), or `NULL` for training data only.
#' @param obs Measured outputs at `newdata`.
#' @param frequency `"monthly"` or `"hourly"`: which Guideline 14 limits apply.
#' @param ndraws Number of posterior draws to use (all by default).
#' @return A data frame (class `koh_metrics`, printed with 2 decimals) with
#'   one row per data set (`training`, `held-out`): `n`, `cvrmse`, `nmbe`
#'   (percent) and `calibrated` (logical).
#' @family metrics
#' @export
#' @examples
#' calibration_metrics(seb_fit, ndraws = 100)
calibration_metrics <- function(fit, newdata = NULL, obs = NULL,
                                frequency = c("monthly", "hourly"), ndraws = NULL) {
  frequency <- match_choice(frequency)
  sets <- evaluation_sets(fit, newdata, obs)
  limits <- switch(frequency, monthly = c(15, 5), hourly = c(30, 10))
  rows <- lapply(names(sets), function(set) {
    pred <- colMeans(predict_draws(fit, sets[[set]]$x, ndraws = ndraws)$y)
    obs <- sets[[set]]$obs
    cv <- cvrmse(obs, pred)
    nb <- nmbe(obs, pred)
    data.frame(set = set, n = length(obs), cvrmse = cv, nmbe = nb,
               calibrated = cv <= limits[1] && abs(nb) <= limits[2])
  })
  structure(do.call(rbind, rows), class = c("koh_metrics", "data.frame"))
}

#' @export
print.koh_metrics <- function(x, ...) {
  rlang::check_dots_empty()
  out <- as.data.frame(unclass(x))
  for (col in intersect(c("cvrmse", "nmbe"), names(out))) {
    out[[col]] <- formatC(out[[col]], format = "f", digits = 2)
  }
  print(out, row.names = FALSE, right = TRUE)
  invisible(x)
}
