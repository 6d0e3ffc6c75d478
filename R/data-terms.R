# Parametric discrepancy terms h' gamma (KOH's mean functions): their
# covariates checked and scaled into the data (extend(), calibrate()).

# Checks covariates of the discrepancy terms and adds them to `data`, divided
# by their range (not centred, so that zero keeps its meaning): `h`
# (n x n_h), `h_scale` and the raw `covariates`.
add_discrepancy_terms <- function(data, covariates, call = rlang::caller_env()) {
  if (is.null(covariates) || ncol(covariates) == 0L) {
    data[c("covariates", "h", "h_scale")] <- list(NULL)
    return(data)
  }
  covariates <- covariate_table(covariates, data$n, call = call)
  check_numeric_complete(covariates, names(covariates), "covariates", call = call)
  check_columns_vary(covariates, call = call)
  h_scale <- vapply(covariates, function(v) diff(range(v)), numeric(1))
  data$covariates <- covariates
  data$h_scale <- h_scale
  data$h <- sweep(as.matrix(covariates), 2, h_scale, "/")
  data
}

# The matrix of discrepancy terms at the field rows (no columns when the fit
# has none).
discrepancy_design <- function(data) {
  data$h %||% matrix(0, data$n, 0)
}

# `covariates` as a numeric table with one row per field row.
covariate_table <- function(covariates, n, call = rlang::caller_env()) {
  covariates <- as_numeric_table(covariates, "covariates", call = call)
  if (nrow(covariates) != n) {
    abort_bayesbem(c("{.arg covariates} must have one row per field row ({n}).",
                     x = "It has {nrow(covariates)}."),
                   "covariates", call = call)
  }
  covariates
}

# Every column of `d` must take more than one value over the field rows.
check_columns_vary <- function(d, call = rlang::caller_env()) {
  spread <- vapply(d, function(v) diff(range(v)), numeric(1))
  check_varies(spread, names(d), "the field rows", call = call)
}
