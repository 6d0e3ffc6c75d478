#' Morris screening of a simulator's parameters
#'
#' The paper's step 2: ranks the uncertain parameters by the Morris
#' elementary-effects method ([sensitivity::morris()], one-at-a-time design
#' with `r` trajectories on a `levels`-level grid), using `mu*` (the mean
#' absolute elementary effect, Campolongo et al. 2007) with `mu` and `sigma`.
#' Inputs are scaled to \[0, 1\] over their ranges and outputs are divided by
#' their mean over all runs, so effects are relative changes of the output
#' over a parameter's whole range and comparable between parameters.
#'
#' @param simulator A `bayesbem_simulator`.
#' @param parameters The parameter table to screen (default: all of the
#'   simulator's parameters).
#' @param r Number of trajectories (the design runs `(k + 1) * r`
#'   simulations for `k` parameters).
#' @param levels Number of grid levels (even; the jump is `levels / 2`).
#' @param seed Random seed of the design.
#' @param effects_on `"total"`: effects on the output summed over all
#'   periods; `"period"`: effects on each period's output.
#' @return A data frame of class `bayesbem_morris`, ranked by `mu_star`:
#'   `parameter`, `mu_star`, `mu`, `sigma`, `rank` (and `period` for
#'   `effects_on = "period"`, where the rank is that of the mean `mu_star` over
#'   periods). A simulator of several outputs (meters) is ranked output by
#'   output, each relative to its own mean, in rows with a first column
#'   `output`: a parameter that drives gas may not touch electricity.
#' @family design
#' @export
#' @examples
#' \donttest{
#' if (requireNamespace("sensitivity", quietly = TRUE)) {
#'   sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#'   m <- screen_morris(sim, r = 10, seed = 1)
#'   m
#'   plot_morris(m)
#' }
#' }
screen_morris <- function(simulator, parameters = simulator$parameters, r = 10, levels = 6,
                          seed = NULL, effects_on = c("total", "period")) {
  rlang::check_installed("sensitivity", reason = "for Morris screening.")
  effects_on <- match_choice(effects_on)
  params <- check_parameter_table(parameters)
  check_count(r)
  check_count(levels)
  if (levels %% 2 != 0) {
    abort_bayesbem("{.arg levels} must be even (the grid jump is {.code levels / 2}).", "argument")
  }
  design <- with_seed(seed, sensitivity::morris(
    model = NULL, factors = params$parameter, r = r,
    design = list(type = "oat", levels = levels, grid.jump = levels / 2),
    binf = params$min, bsup = params$max, scale = TRUE
  ))
  x <- stats::setNames(as.data.frame(design$X), params$parameter)
  table <- simulate_design(simulator, x)
  if (nrow(attr(table, "failed")) > 0L) {
    abort_bayesbem("Morris screening needs every run; {nrow(attr(table, 'failed'))} failed.",
                   "simulation")
  }
  if (is.null(table$output)) {
    out <- morris_table(design, table$eta, nrow(x), params$parameter, effects_on)
  } else {
    # each meter ranked on its own output (the scales of electricity and gas
    # are not comparable), the rows of each output together
    outputs <- unique(table$output)
    out <- do.call(rbind, lapply(outputs, function(k) {
      cbind(output = k, morris_table(design, table$eta[table$output == k], nrow(x),
                                     params$parameter, effects_on))
    }))
  }
  rownames(out) <- NULL
  class(out) <- c("bayesbem_morris", "data.frame")
  out
}

# The effects of one output (`eta`, the runs' outputs in the order of the
# design's rows, each run's periods together), ranked by the mean mu* over
# periods.
morris_table <- function(design, eta, runs, parameters, effects_on) {
  runs <- matrix(eta, nrow = runs, byrow = TRUE)
  runs <- runs / mean(runs)
  if (effects_on == "total") {
    out <- data.frame(parameter = parameters, morris_effects(design, rowSums(runs) / ncol(runs)))
  } else {
    out <- do.call(rbind, lapply(seq_len(ncol(runs)), function(j) {
      data.frame(parameter = parameters, period = j, morris_effects(design, runs[, j]))
    }))
  }
  mean_mu_star <- tapply(out$mu_star, out$parameter, mean)[parameters]
  out$rank <- match(out$parameter, parameters[order(-mean_mu_star)])
  out[order(out$rank, out$period %||% rep(0, nrow(out))), ]
}

morris_effects <- function(design, y) {
  m <- sensitivity::tell(design, y)
  ee <- m$ee
  data.frame(mu_star = colMeans(abs(ee)), mu = colMeans(ee), sigma = apply(ee, 2, stats::sd),
             row.names = NULL)
}

#' @export
print.bayesbem_morris <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  cat("Morris screening (effects relative to the mean output, over each parameter's range)\n")
  print(as.data.frame(unclass(x)), digits = digits, row.names = FALSE)
  invisible(x)
}
