#' @export
print.bayesbem_portfolio <- function(x, level = 0.9, ...) {
  rlang::check_dots_empty()
  s <- summary(x, level = level)
  b <- s$buildings
  status <- table(factor(b$status, c("done", "failed", "refused", "missing")))
  cat_lines(paste("A portfolio of {nrow(b)} building{?s} in {.file {x$dir}}:",
                  "{status[['done']]} done, {status[['failed']]} failed, {status[['refused']]} refused, {status[['missing']]} missing."))
  if (!is.null(s$total)) {
    cat_lines("Total savings {signif(s$total$savings, 3)} ({100 * level} % interval {signif(s$total$lower, 3)} to {signif(s$total$upper, 3)}) over {s$total$buildings} building{?s}; FSU {signif(s$total$fsu, 2)} (Guideline 14's aggregate: {signif(s$total$fsu_guideline14, 2)}).")
  }
  print_rounded(b[setdiff(names(b), c("verdict", "error"))], 3)
  stopped <- b[!is.na(b$error), ]
  # errors as they are (cli would read braces in them)
  first_lines <- vapply(strsplit(stopped$error, "\n"), `[`, "", 1L)
  if (nrow(stopped) > 0L) cat(sprintf("%s (%s): %s", stopped$id, stopped$status, first_lines), sep = "\n")
  invisible(x)
}

#' Summarise a portfolio: each building, and the total savings
#'
#' One row per building: its status, convergence, Guideline 14's CV(RMSE)
#' and NMBE of the calibrated predictions at the calibration
#' ([calibration_metrics()]), the lowest monthly share of hours present
#' (hourly data, [data_sufficiency()]), the discrepancy's verdict
#' ([discrepancy()]), with a retrofit its savings with their interval
#' and fractional savings uncertainty (FSU: the interval's half-width over
#' the savings) beside Guideline 14's, the number of warnings its job had
#' (in its record's `warnings`), its time and, when it failed, its error.
#'
#' The portfolio's total savings are the sum of the buildings' savings
#' draw by draw: the buildings are calibrated independently (no parameter
#' or discrepancy is shared between them), so the `k`-th draws of all
#' buildings are a draw of the total. Beside it, Guideline 14's aggregate
#' FSU for independent savings: the buildings' absolute uncertainties
#' (FSU times savings) added in quadrature, over the total.
#'
#' @param object A [calibrate_portfolio()] result.
#' @template args-level
#' @param ... Unused.
#' @return A list: `buildings` (the table) and `total` (`buildings`,
#'   `savings`, `lower`, `upper`, `fsu`, `fsu_guideline14`; `NULL` without
#'   savings).
#' @family portfolio
#' @export
summary.bayesbem_portfolio <- function(object, level = 0.9, ...) {
  rlang::check_dots_empty()
  check_probability(level)
  rows <- lapply(object$records, portfolio_row, level = level)
  buildings <- do.call(rbind, rows)
  rownames(buildings) <- NULL
  list(buildings = buildings, total = portfolio_total(object$records, level))
}

# One building's row of summary(): NA where the building has no result.
portfolio_row <- function(record, level) {
  value <- function(name) record[[name]] %||% NA
  saved <- record$savings_draws
  bounds <- if (!is.null(saved)) column_intervals(cbind(saved), level) else c(NA, NA)
  data.frame(id = record$id, status = record$status, converged = value("converged"),
             rhat = value("rhat"), cvrmse = value("cvrmse"), nmbe = value("nmbe"),
             sufficiency = value("sufficiency"), verdict = as.character(value("verdict")),
             savings = if (!is.null(saved)) mean(saved) else NA_real_,
             lower = bounds[1], upper = bounds[2],
             fsu = if (!is.null(saved)) half_width(bounds) / abs(mean(saved)) else NA_real_,
             fsu_guideline14 = guideline14_at(record, level),
             warnings = length(record$warnings), seconds = value("seconds"),
             error = as.character(value("error")))
}

half_width <- function(bounds) (bounds[2] - bounds[1]) / 2

# A record's Guideline 14 FSU (stored at 90 %) at `level`: the formula's
# Student quantile rescaled (its other factors do not depend on the level).
guideline14_at <- function(record, level) {
  if (is.null(record$fsu_guideline14)) {
    return(NA_real_)
  }
  df <- record$guideline14_df
  record$fsu_guideline14 * stats::qt(interval_probs(level)[2], df) /
    stats::qt(interval_probs(0.9)[2], df)
}

# The total savings of the buildings with savings: their draws summed draw
# by draw, and Guideline 14's aggregate FSU. NULL when none has savings.
portfolio_total <- function(records, level, call = rlang::caller_env()) {
  saved <- Filter(function(r) !is.null(r$savings_draws), records)
  if (length(saved) == 0L) {
    return(NULL)
  }
  ndraws <- vapply(saved, function(r) length(r$savings_draws), integer(1))
  if (length(unique(ndraws)) > 1L) {
    abort_bayesbem(c("The buildings' savings have different numbers of draws ({.val {unique(ndraws)}}), so they cannot be summed draw by draw.",
                     i = "Rerun the buildings with another {.arg ndraws} (delete their files) so that all have the same."),
                   "argument", call = call)
  }
  total <- Reduce(`+`, lapply(saved, `[[`, "savings_draws"))
  bounds <- column_intervals(cbind(total), level)
  absolute <- vapply(saved, function(r) guideline14_at(r, level) * abs(mean(r$savings_draws)),
                     numeric(1))
  data.frame(buildings = length(saved), savings = mean(total), lower = bounds[1],
             upper = bounds[2], fsu = half_width(bounds) / abs(mean(total)),
             fsu_guideline14 = sqrt(sum(absolute^2)) / abs(mean(total)))
}

#' Savings of a portfolio's buildings and their total
#'
#' Each building's savings (mean and central interval of its paired
#' posterior draws) and the portfolio's total ([summary.bayesbem_portfolio()]),
#' in two panels.
#'
#' @param x A [calibrate_portfolio()] result with savings.
#' @template args-level
#' @param ... Unused.
#' @return `plot_portfolio()`: a ggplot. `plot_portfolio_data()`: a data
#'   frame with one row per building with savings and one for the total:
#'   `id`, `panel` (`"buildings"`, `"portfolio"`), `savings`, `lower`,
#'   `upper`.
#' @family plots
#' @family portfolio
#' @export
plot_portfolio <- function(x, level = 0.9, ...) {
  rlang::check_dots_empty()
  d <- plot_portfolio_data(x, level = level)
  ggplot2::ggplot(d, ggplot2::aes(x = .data$savings, y = .data$id)) +
    ggplot2::geom_vline(xintercept = 0, colour = colour_of("reference")) +
    ggplot2::geom_pointrange(ggplot2::aes(xmin = .data$lower, xmax = .data$upper),
                             colour = colour_of("savings")) +
    ggplot2::facet_grid(rows = ggplot2::vars(.data$panel), scales = "free", space = "free_y") +
    ggplot2::labs(x = sprintf("savings (mean and %s %% interval)", 100 * level), y = NULL,
                  caption = "the total: the buildings' paired draws summed draw by draw") +
    theme_bayesbem()
}

#' @export
plot.bayesbem_portfolio <- function(x, ...) plot_portfolio(x, ...)

#' @rdname plot_portfolio
#' @export
plot_portfolio_data <- function(x, level = 0.9, ...) {
  rlang::check_dots_empty()
  check_plotted(x, "bayesbem_portfolio", "calibrate_portfolio")
  s <- summary(x, level = level)
  if (is.null(s$total)) {
    abort_bayesbem("{.arg x} has no savings: give {.arg retrofit} to {.fn calibrate_portfolio}.",
                   "argument")
  }
  b <- s$buildings[!is.na(s$buildings$savings), ]
  rbind(data.frame(id = b$id, panel = "buildings", savings = b$savings, lower = b$lower,
                   upper = b$upper),
        data.frame(id = "total", panel = "portfolio", savings = s$total$savings,
                   lower = s$total$lower, upper = s$total$upper))
}
