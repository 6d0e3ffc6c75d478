# Summaries of draws-by-columns matrices shared by the prediction,
# scenario, savings and discrepancy tools: quantiles, central intervals of
# a `level`, per-period tables with their total, weighted totals of outputs.

# The quantiles that bound a central interval of `level`.
interval_probs <- function(level) c((1 - level) / 2, (1 + level) / 2)

# Quantiles of each column of a draws matrix: one row per column, one column
# per probability, named q5, q50, ...
column_quantiles <- function(draws, probs) {
  q <- matrix(t(apply(draws, 2, stats::quantile, probs = probs, names = FALSE)),
              ncol = length(probs))
  colnames(q) <- quantile_names(probs)
  q
}

# Column names of quantiles: q5, q50, q95 for 0.05, 0.5, 0.95.
quantile_names <- function(probs) paste0("q", signif(100 * probs, 3))

# The central `level` interval of each column of a draws matrix from order
# statistics: X_(k) and X_(j) of the n draws, j = covering_rank(n, (1 +
# level) / 2), k = n + 1 - j. A new draw of the same distribution falls
# inside with probability (j - k) / (n + 1) >= level whatever n (the draws
# being exchangeable), where the empirical quantiles of a few draws cover
# less than `level`. A matrix: a row per column of `draws`, columns lower
# and upper (NA for a column with a missing draw).
column_intervals <- function(draws, level) {
  n <- nrow(draws)
  upper <- covering_rank(n, (1 + level) / 2)
  ranks <- c(n + 1L - upper, upper)
  bounds <- matrix(apply(draws, 2, function(x) {
    if (anyNA(x)) c(NA_real_, NA_real_) else sort(x, partial = ranks)[ranks]
  }), nrow = 2L)
  cbind(lower = bounds[1, ], upper = bounds[2, ])
}

# The rank j of the order statistic X_(j) of n draws that a new draw stays
# below with probability j / (n + 1) >= p: ceiling((n + 1) p). With fewer
# than p / (1 - p) draws no rank reaches p; the largest is taken, with a
# warning that says how many draws would.
covering_rank <- function(n, p) {
  rank <- ceiling((n + 1) * p - 1e-8)
  if (rank > n) {
    needed <- ceiling(p / (1 - p) - 1e-8)
    warn_bayesbem(c("{n} draw{?s} are too few for this interval.",
                    i = "A new draw exceeds the largest of them {round(100 / (n + 1), 1)} % of the time, more than the {signif(100 * (1 - p), 3)} % the interval allows at that end.",
                    i = "Take {.arg ndraws} at least {needed}."),
                  "draws")
    rank <- n
  }
  as.integer(rank)
}

# The sd and the central `level` interval (column_intervals()) of each
# column of `draws`: a data frame with columns sd, lower and upper.
interval_table <- function(draws, level) {
  bounds <- column_intervals(draws, level)
  data.frame(sd = apply(draws, 2, stats::sd), lower = bounds[, "lower"],
             upper = bounds[, "upper"], row.names = NULL)
}

# Data frame of `inputs` with the mean, sd, median and the bounds of the
# central `level` interval of each column of `draws` (column_intervals(),
# named q5 and q95 at 0.9).
summarise_columns <- function(draws, inputs, level) {
  bounds <- column_intervals(draws, level)
  colnames(bounds) <- quantile_names(interval_probs(level))
  data.frame(inputs, mean = colMeans(draws), sd = apply(draws, 2, stats::sd),
             bounds[, 1, drop = FALSE], column_quantiles(draws, 0.5), bounds[, 2, drop = FALSE],
             row.names = NULL)
}

# Tables by output (a named list) stacked, a first column `output` naming
# each row's.
stack_outputs <- function(tables) {
  rows <- Map(function(k, d) data.frame(output = k, d, check.names = FALSE), names(tables), tables)
  out <- do.call(rbind, unname(rows))
  rownames(out) <- NULL
  out
}

# Row labels of per-period tables with their total.
total_labels <- function(n) c(as.character(seq_len(n)), "total")

# Draws by periods with a last column, their total over the periods.
with_total <- function(draws) cbind(draws, rowSums(draws))

# summarise_columns() of each period's draws and of their total.
draws_with_total <- function(draws, inputs, level) {
  inputs <- rbind(inputs, inputs[NA_integer_, , drop = FALSE])
  summarise_columns(with_total(draws), data.frame(period = total_labels(ncol(draws)), inputs),
                    level)
}

# The weighted total of outputs' draws-by-columns matrices `parts` (by
# output), draw by draw, `total` the weights by output. When the outputs'
# rows may be other draws, `draw` gives each output's draws' indices, and
# the total is over the draws all of them have, in the first's order.
weighted_total <- function(total, parts, draw = NULL) {
  shared <- if (!is.null(draw)) Reduce(intersect, draw)
  Reduce(`+`, lapply(names(total), function(k) {
    rows <- if (is.null(shared)) seq_len(nrow(parts[[k]])) else match(shared, draw[[k]])
    total[[k]] * parts[[k]][rows, , drop = FALSE]
  }))
}
