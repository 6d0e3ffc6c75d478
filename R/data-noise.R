# The observation noise of periods of different lengths (koh_data(),
# "Noise"). A period's total sums its days' errors; independent days give
#   var(e_i) = w_i / lambda_e,  w_i = days_i / mean(days over the field rows),
# so 1 / lambda_e is the noise variance of a field period of average length.
# Periods of one length (calendar months, days, hours) have no input
# `days`, and every w_i is 1: the paper's model.

# The mean length of the field's periods, the reference of every weight
# (NULL when the rows carry no `days`), kept in the data's scaling so that
# new periods (predictions, scenarios) are weighed on the fit's reference.
noise_reference <- function(x_raw) {
  if ("days" %in% colnames(x_raw)) mean(x_raw[, "days"]) else NULL
}

# Each row's w_i for a table of inputs in physical units (the field's by
# default), from its `days`, on the fit's reference.
noise_weights <- function(data, x = data$field) {
  period_weights(x, data$scaling$days)
}

# w_i of the periods of a table of inputs, on the mean of its own `days`
# unless a reference is given.
period_weights <- function(x, reference = noise_reference(x)) {
  if (is.null(reference)) rep(1, NROW(x)) else x[, "days"] / reference
}

# Each field row's noise variance for one draw `par` of a fit whose
# geometry `g` (gp_geometry()) holds the rows' weights.
noise_var <- function(g, par) g$noise / par$lambda_e

# Observation noise N(0, w_i / lambda_e), standardised: draws (rows) by
# periods of weights `w` (columns).
noise_matrix <- function(draws, w) {
  sd_e <- 1 / sqrt(vapply(draws, `[[`, numeric(1), "lambda_e"))
  matrix(stats::rnorm(length(draws) * length(w)), length(draws)) * outer(sd_e, sqrt(w))
}
