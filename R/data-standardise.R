# Scaling of method.md section 1, and its inverse. Every function takes the
# `scaling` list that koh_data() stores, so predictions and reports use
# exactly the constants the fit used.

scale_y <- function(y, scaling) (y - scaling$y_center) / scaling$y_scale

unscale_y <- function(z, scaling) z * scaling$y_scale + scaling$y_center

# Differences and standard deviations scale without the centre.
unscale_y_spread <- function(z, scaling) z * scaling$y_scale

scale_columns <- function(v, lo, hi) {
  v <- as.matrix(v)
  sweep(sweep(v, 2, lo, "-"), 2, hi - lo, "/")
}

unscale_columns <- function(u, lo, hi) {
  u <- as.matrix(u)
  sweep(sweep(u, 2, hi - lo, "*"), 2, lo, "+")
}

scale_x <- function(x, scaling) scale_columns(x, scaling$x_min, scaling$x_max)

unscale_x <- function(u, scaling) unscale_columns(u, scaling$x_min, scaling$x_max)

# Calibration parameters are first put on their scale (parameter_scales():
# identity, log or reciprocal; each increasing), then mapped to [0, 1] by
# the design's range on that scale (`t_min`, `t_max`); the emulator works
# there. Priors stay in physical units (tf_prior_lpdf() in
# koh_functions.stan). One parameter `k` at a time:
scale_t1 <- function(v, scaling, k) {
  (scale_functions[[t_scales(scaling)[[k]]]]$to(v) - scaling$t_min[[k]]) /
    (scaling$t_max[[k]] - scaling$t_min[[k]])
}

unscale_t1 <- function(u, scaling, k) {
  scale_functions[[t_scales(scaling)[[k]]]]$from(
    u * (scaling$t_max[[k]] - scaling$t_min[[k]]) + scaling$t_min[[k]])
}

scale_t <- function(t, scaling) {
  t <- as.matrix(t)
  for (k in seq_len(ncol(t))) t[, k] <- scale_t1(t[, k], scaling, k)
  t
}

unscale_t <- function(u, scaling) {
  u <- as.matrix(u)
  for (k in seq_len(ncol(u))) u[, k] <- unscale_t1(u[, k], scaling, k)
  u
}

# The design's range of each parameter in physical units (every scale is
# increasing, so 0 and 1 map to the ends).
t_bounds <- function(scaling) {
  ends <- unscale_t(matrix(c(0, 1), 2, length(scaling$t_min)), scaling)
  list(lower = stats::setNames(ends[1, ], names(scaling$t_min)),
       upper = stats::setNames(ends[2, ], names(scaling$t_min)))
}

# Fits saved before parameter scales existed (scaling without `t_scale`)
# used the identity.
t_scales <- function(scaling) {
  scaling$t_scale %||% stats::setNames(rep("identity", length(scaling$t_min)), names(scaling$t_min))
}

scale_functions <- list(
  identity = list(to = function(v) v, from = function(s) s),
  log = list(to = log, from = exp),
  # -1 / v rather than 1 / v keeps the parameter's order on [0, 1]
  reciprocal = list(to = function(v) -1 / v, from = function(s) -1 / s)
)

# Checks new observable inputs, warns on extrapolation, and scales them.
scale_newdata <- function(data, newdata, arg = "newdata", call = rlang::caller_env()) {
  x_names <- data$names$x
  if (!is.data.frame(newdata)) {
    abort_bayesbem(c("{.arg {arg}} must be a data frame with columns {.field {x_names}}.",
                     x = "It is {.obj_type_friendly {newdata}}."),
                   "input_type", call = call)
  }
  missing <- setdiff(x_names, names(newdata))
  if (length(missing) > 0L) {
    abort_bayesbem(c("{.arg {arg}} has no column{?s} {.field {missing}}.",
                     i = "It needs the observable inputs the model was calibrated on: {.field {x_names}}."),
                   "columns", call = call)
  }
  if (nrow(newdata) < 1L) {
    abort_bayesbem("{.arg {arg}} has no rows.", "too_few_rows", call = call)
  }
  check_numeric_complete(newdata, x_names, arg, call = call)
  x <- as.matrix(newdata[x_names])
  s <- data$scaling
  # rounding (weather averaged apart from the fit's) is not extrapolation
  slack <- 1e-8 * (s$x_max - s$x_min)
  outside <- x_names[colSums(sweep(x, 2, s$x_min - slack, "<") |
                               sweep(x, 2, s$x_max + slack, ">")) > 0]
  if (length(outside) > 0L) {
    warn_bayesbem(c("{.arg {arg}} is outside the range the model was calibrated on in {.field {outside}}.",
                    i = "These predictions extrapolate the Gaussian processes; expect them to revert to the mean.",
                    i = "For another period's weather, rerun the simulator there instead: {.fn predict_scenario}."),
                  "extrapolation")
  }
  scale_x(x, s)
}
