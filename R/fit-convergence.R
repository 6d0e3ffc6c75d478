#' Convergence diagnostics of a KOH fit
#'
#' Computes, for every sampled parameter (calibration parameters in physical
#' units, GP hyperparameters; a modular fit's emulator hyperparameters are
#' fixed at their stage-1 mode and left out), the rank-normalised split
#' R-hat and the bulk and tail effective sample sizes of the posterior
#' package, and from the sampler the number of divergent transitions, of
#' iterations that hit the maximum tree depth, and the E-BFMI of each
#' chain. Raises one warning of class
#' `bayesbem_warning_convergence`, with a plain-language hint, when any
#' R-hat is at least `rhat_max`, any ESS is below `ess_min`, any transition
#' diverged, any iteration hit the maximum tree depth, or any chain's E-BFMI
#' is below `ebfmi_min`; [calibrate()] calls it at the end of every fit
#' (rstan's own, unclassed warnings of these kinds are not shown).
#'
#' When every parameter that fails is one of the emulator's hyperparameters
#' (`beta_eta`, `lambda_eta`, the mean's `b`; sampled in a joint fit only)
#' and the sampler had no trouble, the hint says so and advises runs where
#' the posterior lies ([design_posterior()]): with few runs such failures
#' are common while the calibration parameters converge, and runs from
#' [design_posterior()] removed most of them
#' (`inst/notes/decisions/G2-runs-where-the-posterior-lies.md`). When stage 2
#' of a modular fit kept chains in a minor mode that puts the calibration
#' parameters elsewhere (see `minor_modes` in [calibrate()]), the hint names
#' them and advises checking the emulator over both modes.
#'
#' @param fit A `bayesbem_fit`, or a fit on several outputs (the shared
#'   parameters are checked once, each output's own under its name,
#'   `"gas:lambda_e"`).
#' @param rhat_max R-hat at or above which a parameter has not converged.
#' @param ess_min Smallest acceptable bulk and tail ESS; by default 100 per
#'   chain (400 for 4 chains).
#' @param ebfmi_min Smallest acceptable E-BFMI of a chain (0.3, the
#'   threshold of Betancourt 2016 that Stan's documentation uses).
#' @param warn Raise the warning (`TRUE`) or only return the table.
#' @return A data frame of class `bayesbem_convergence` with columns `variable`,
#'   `rhat`, `ess_bulk`, `ess_tail` and `ok`, and an attribute `sampler`: a
#'   list with `divergent`, `treedepth_hits`, `max_treedepth` and `ebfmi`
#'   (one per chain).
#' @family diagnostics
#' @export
#' @examples
#' check_convergence(seb_fit, warn = FALSE)
check_convergence <- function(fit, rhat_max = 1.01, ess_min = NULL, ebfmi_min = 0.3,
                              warn = TRUE) {
  ess_min <- ess_min %||% (100 * kept_chains(fit))
  s <- convergence_rows(fit)
  rownames(s) <- NULL
  sampler <- fit_sampler_diagnostics(fit)
  s$ok <- s$rhat < rhat_max & s$ess_bulk >= ess_min & s$ess_tail >= ess_min
  out <- structure(s, class = c("bayesbem_convergence", "data.frame"), sampler = sampler,
                   thresholds = list(rhat_max = rhat_max, ess_min = ess_min,
                                     ebfmi_min = ebfmi_min),
                   emulator = emulator_variables(fit),
                   kept_moved = fit$settings$kept_moved %||% integer(0))
  if (warn) warn_convergence(out)
  out
}

# R-hat and ESS of the variables a fit samples; for a fit on several
# outputs, the shared parameters once and each output's own under its name
# (output_variables()).
convergence_rows <- function(fit) UseMethod("convergence_rows")

convergence_rows.bayesbem_fit <- function(fit) {
  s <- summarise_fit(fit, rhat = posterior::rhat, ess_bulk = posterior::ess_bulk,
                     ess_tail = posterior::ess_tail)
  s[!s$variable %in% fixed_variables(fit), , drop = FALSE]
}

convergence_rows.bayesbem_fit_outputs <- function(fit) {
  rows <- lapply(names(fit$outputs), function(k) {
    s <- convergence_rows(fit$outputs[[k]])
    v <- output_variables(s$variable, k, names(fit$outputs), fit$data$names$t)
    s <- s[s$variable %in% names(v), , drop = FALSE]
    s$variable <- unname(v[s$variable])
    s
  })
  do.call(rbind, rows)
}

warn_convergence <- function(conv) {
  th <- attr(conv, "thresholds")
  sp <- attr(conv, "sampler")
  problems <- character()
  high_rhat <- conv$variable[conv$rhat >= th$rhat_max]
  if (length(high_rhat) > 0L) {
    problems <- c(problems, x = cli::format_inline(
      "R-hat >= {th$rhat_max} for {.field {high_rhat}}: the chains disagree."))
  }
  low_ess <- conv$variable[pmin(conv$ess_bulk, conv$ess_tail) < th$ess_min]
  if (length(low_ess) > 0L) {
    problems <- c(problems, x = cli::format_inline(
      "Bulk or tail ESS < {th$ess_min} for {.field {low_ess}}: too few effective draws."))
  }
  draw_problems <- length(problems)
  if (sp$divergent > 0L) {
    problems <- c(problems, x = cli::format_inline(
      "{sp$divergent} divergent transition{?s}: the sampler missed part of the posterior."))
  }
  if (sp$treedepth_hits > 0L) {
    problems <- c(problems, x = cli::format_inline(
      "{sp$treedepth_hits} iteration{?s} hit the maximum tree depth ({sp$max_treedepth}): the sampler stopped its trajectories early."))
  }
  low_bfmi <- which(sp$ebfmi < th$ebfmi_min)
  if (length(low_bfmi) > 0L) {
    problems <- c(problems, x = cli::format_inline(
      "E-BFMI < {th$ebfmi_min} in {cli::qty(length(low_bfmi))}chain{?s} {low_bfmi}: the sampler explores the energy (the hyperparameters' scale) poorly."))
  }
  if (length(problems) == 0L) {
    return(invisible(conv))
  }
  # the sampler had no trouble, and every parameter that failed is one of
  # the emulator's hyperparameters
  emulator_only <- length(problems) == draw_problems &&
    all(union(high_rhat, low_ess) %in% attr(conv, "emulator"))
  kept <- attr(conv, "kept_moved")
  hint <- if (length(kept) > 0L) {
    c(i = paste0(kept_modes_said(kept), ". ", kept_modes_advice()))
  } else if (emulator_only) emulator_modes_hint() else
    c(i = paste("Run more iterations (e.g. double {.arg iter}); for divergences",
                "raise {.code control = list(adapt_delta = 0.995)}, for tree depth",
                "{.code control = list(max_treedepth = 12)}; check",
                "{.code plot(fit, type = \"trace\")}."))
  warn_bayesbem(c("The calibration may not have converged.", problems, hint), "convergence")
  invisible(conv)
}

# With few runs per parameter the chains that disagree only on the
# emulator's length scales sit in modes of similar posterior mass, seldom
# crossed; runs where the posterior lies removed them in most problems
# measured (inst/notes/decisions/G2-runs-where-the-posterior-lies.md).
emulator_modes_hint <- function() {
  c(i = paste("Only the emulator's hyperparameters failed: the calibration parameters,",
              "the discrepancy and the noise passed. Few runs leave the emulator's length",
              "scales several modes of similar posterior mass, which chains seldom cross."),
    i = paste("Add runs where the posterior lies ({.fn design_posterior}, then",
              "{.fn simulate_design}) and fit again."))
}

#' @export
print.bayesbem_convergence <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  sp <- attr(x, "sampler")
  th <- attr(x, "thresholds")
  # a subset of the table keeps the class, but a column subset loses the attributes
  if (!is.null(x$ok) && !is.null(th)) {
    cat(sprintf("Convergence: R-hat < %s and bulk/tail ESS >= %d for %d of %d parameters\n",
                th$rhat_max, th$ess_min, sum(x$ok), nrow(x)))
  }
  if (!is.null(sp)) {
    cat(sprintf("Sampler: %d divergent transitions; %d iterations at max tree depth %d; E-BFMI %s\n\n",
                sp$divergent, sp$treedepth_hits, sp$max_treedepth,
                paste(format(sp$ebfmi, digits = 2), collapse = ", ")))
  }
  out <- as.data.frame(unclass(x))
  digits_of <- c(rhat = 3, ess_bulk = 0, ess_tail = 0)
  for (col in intersect(names(digits_of), names(out))) {
    out[[col]] <- round(out[[col]], digits_of[[col]])
  }
  print(out, row.names = FALSE)
  invisible(x)
}

# Calibration parameters whose posterior piles against a limit of their
# range (the runs' range, tf = 0 or 1, which bounds the prior): more than `share` of the draws
# within `edge` of the range from it, where a posterior as flat as the
# prior holds `edge` of them. One row per parameter and limit: `parameter`,
# `limit` ("minimum", "maximum"), `value` (physical units), `share`.
range_limits <- function(fit, edge = 0.02, share = 0.1) {
  one <- output_fit_list(fit)[[1]]
  scaling <- one$data$scaling
  tf <- posterior::as_draws_matrix(posterior::subset_draws(one$draws, variable = "tf"))
  rows <- lapply(seq_len(ncol(tf)), function(k) {
    near <- c(minimum = mean(tf[, k] < edge), maximum = mean(tf[, k] > 1 - edge))
    at <- names(near)[near > share]
    if (length(at) == 0L) return(NULL)
    data.frame(parameter = one$data$names$t[k], limit = at,
               value = unscale_t1(ifelse(at == "minimum", 0, 1), scaling, k),
               share = unname(near[at]))
  })
  do.call(rbind, c(list(data.frame(parameter = character(), limit = character(),
                                   value = numeric(), share = numeric())), rows))
}

# The warning calibrate() raises when a posterior piles against a limit:
# the data ask for a value the range excludes, or for a cause the model
# lacks, which a parameter at its limit stands in for.
warn_range_limits <- function(fit) {
  piled <- range_limits(fit)
  if (nrow(piled) == 0L) {
    return(invisible(piled))
  }
  lines <- sprintf("%s at its %s, %s (%d %% of the draws within 2 %% of the range from it)",
                   piled$parameter, piled$limit, format(signif(piled$value, 3)),
                   round(100 * piled$share))
  warn_bayesbem(c("{nrow(piled)} posterior{?s} pile{?s/} against a limit of the parameter's range:",
                  stats::setNames(lines, rep("*", length(lines))),
                  i = "The limit is the runs' range: if a value beyond it is physical, widen the parameter's range and rerun the design ({.fn design_lhs}); if not, the model lacks a cause the data show (see {.fn discrepancy} and {.fn explain_discrepancy}), and a parameter at its limit is not a calibrated value."),
                "range_limit")
  invisible(piled)
}
