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
  colnames(q) <- paste0("q", signif(100 * probs, 3))
  q
}

# Data frame of `inputs` with the mean, sd, median and the bounds of the
# central `level` interval of each column of `draws` (q5, q50, q95 at 0.9).
summarise_columns <- function(draws, inputs, level) {
  probs <- sort(c(interval_probs(level), 0.5))
  data.frame(inputs, mean = colMeans(draws), sd = apply(draws, 2, stats::sd),
             column_quantiles(draws, probs), row.names = NULL)
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
