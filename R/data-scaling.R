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

scale_t <- function(t, scaling) scale_columns(t, scaling$t_min, scaling$t_max)

unscale_t <- function(u, scaling) unscale_columns(u, scaling$t_min, scaling$t_max)
