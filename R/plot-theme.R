# The one look of every bayesbem plot (bayesplot's bayesplot-colors.R and
# bayesplot-ggplot-themes.R are the model): a colour per role, a theme, and
# the quantile box the prediction, savings and study plots share.

# Colours by role: the model's draws in blue, measurements and alarms in
# red, priors and what the data left alone in grey, savings in green.
bayesbem_colours <- c(
  model = "#1b6ca8",
  model_light = "#6fa8d6",
  model_fill = "#cfe0ef",
  data = "#c0392b",
  prior = "grey45",
  reference = "grey50",
  savings = "#2e7d32",
  savings_fill = "#d5ecd4"
)

# The colour of one role (an unknown role is a bug, so it stops).
colour_of <- function(role) {
  colour <- bayesbem_colours[role]
  stopifnot(!anyNA(colour))
  unname(colour)
}

# ggplot2's black-and-white theme, with the legend below the panel where a
# plot has one that would narrow the panels (`legend = "bottom"`).
theme_bayesbem <- function(legend = NULL) {
  theme <- ggplot2::theme_bw()
  if (!is.null(legend)) theme <- theme + ggplot2::theme(legend.position = legend)
  theme
}

# Stops unless `x`, the object a plot draws, is of `class`: a result of
# `maker` (a function's name).
check_plotted <- function(x, class, maker, arg = rlang::caller_arg(x),
                          call = rlang::caller_env()) {
  if (!inherits(x, class)) {
    abort_bayesbem("{.arg {arg}} must come from {.fn {maker}}, not {describe_value(x)}.",
                   "argument", call = call)
  }
}

# Box-plot statistics of each column of a draws matrix: whiskers at the 5 %
# and 95 % quantiles, box at the quartiles.
box_stats <- function(draws) {
  as.data.frame(column_quantiles(draws, c(0.05, 0.25, 0.5, 0.75, 0.95)))
}

# A box per row of box_stats(): drawn from the quantiles, not computed by
# ggplot2 (whose whiskers follow Tukey's rule); `mapping` adds aesthetics
# (a box width per row, for panels whose x axes differ). Boxes read a
# `width` column in every ggplot2 version, but only from ggplot2 3.5 is
# `width` among geom_boxplot()'s aesthetics; before, the layer warns that
# it ignores it, which is not so, and that warning is muffled.
geom_quantile_box <- function(mapping = ggplot2::aes(), ...) {
  box <- ggplot2::aes(ymin = .data$q5, lower = .data$q25, middle = .data$q50,
                      upper = .data$q75, ymax = .data$q95)
  box[names(mapping)] <- mapping
  withCallingHandlers(
    ggplot2::geom_boxplot(mapping = box, stat = "identity", ...),
    warning = function(w) {
      if (grepl("unknown aesthetics: width", conditionMessage(w), fixed = TRUE)) {
        invokeRestart("muffleWarning")
      }
    })
}
