# Chains in minor modes (inst/notes/decisions/F8-minor-modes.md): each chain's mode's
# posterior mass from its own draws, which chains to drop, restart or
# keep, and the messages that say so.

# What to do with the chains in a minor mode (minor_mode_chains()): its list
# with `kept` (the minor chains kept as they ran) and `minor_tf`
# (minor_mode_tf()). With `keep_moved` (stage 2 of a modular fit) chains
# whose mode puts a calibration parameter outside the main mode's 90 %
# interval are kept: with the emulator fixed, such a mode can be the
# emulator's error between runs rather than the posterior's
# (inst/notes/decisions/F8-minor-modes.md), and R-hat
# then shows the disagreement instead of a confident wrong answer.
settle_minor_modes <- function(draws, divergent, keep_moved = FALSE) {
  modes <- minor_mode_chains(draws, divergent)
  minor <- c(modes$drop, modes$restart)
  modes$minor_tf <- minor_mode_tf(draws, minor)
  modes$kept <- integer(0)
  if (keep_moved && any(moved_tf(modes$minor_tf))) {
    modes$kept <- minor
    modes$drop <- modes$restart <- integer(0)
    modes$from <- NULL
  }
  modes
}

# Where the chains `minor` put the calibration parameters, against the other
# chains: a 3 x q matrix (columns tf[1], ..., on the [0, 1] scale) of the
# minor chains' median and the other chains' 5 % and 95 % quantiles; NULL
# without minor chains or calibration parameters.
minor_mode_tf <- function(draws, minor) {
  tf <- grep("^tf\\[", dimnames(draws)[[3]], value = TRUE)
  if (length(minor) == 0L || length(tf) == 0L) {
    return(NULL)
  }
  vapply(stats::setNames(nm = tf), function(v) {
    c(median = stats::median(draws[, minor, v]),
      stats::setNames(stats::quantile(draws[, -minor, v], c(0.05, 0.95), names = FALSE),
                      c("lower", "upper")))
  }, numeric(3))
}

# Which calibration parameters the minor mode put outside the main mode's
# 90 % interval (minor_mode_tf()).
moved_tf <- function(minor_tf) {
  if (is.null(minor_tf)) {
    return(logical(0))
  }
  minor_tf["median", ] < minor_tf["lower", ] | minor_tf["median", ] > minor_tf["upper", ]
}

# The chains stuck in a minor mode and what to do with them: a list of
# `drop` and `restart` (chain indices) and `from` (the chain to restart
# them from). Each chain's mode gets a Laplace estimate of its log posterior
# mass from the chain's draws, log m = mean(lp__) + log det(S) / 2 + (terms
# common to all chains), S the covariance of the draws on Stan's
# unconstrained scale (for a Gaussian mode, log m = lp(peak) + d log(2 pi) / 2
# + log det(S) / 2 and mean(lp__) = lp(peak) - d / 2). A chain whose mode has
# less than exp(-gap) of the best chain's mass holds draws the posterior
# almost never gives; R-hat would only report that the chains disagree.
# Chains within `gap` of the best are kept even when they disagree: modes of
# similar mass are the posterior's, and check_convergence() reports them.
# The minor chains are dropped when two chains remain to check each other;
# when the best chain stands alone they are run again from its draws
# instead, provided it had no divergent transition (`divergent`, per
# chain). Why a gap of 5 (a mode under 0.7 % of the mass):
# inst/notes/decisions/F8-minor-modes.md.
minor_mode_chains <- function(draws, divergent = integer(dim(draws)[2]), gap = 5) {
  none <- list(drop = integer(0), restart = integer(0), from = NULL)
  if (dim(draws)[2] < 2L) {
    return(none)
  }
  log_mass <- vapply(seq_len(dim(draws)[2]), function(k) {
    u <- unconstrained_draws(draws[, k, , drop = TRUE])
    u <- u[, apply(u, 2, stats::var) > 0, drop = FALSE]
    det <- determinant(stats::cov(u), logarithm = TRUE)
    mean(draws[, k, "lp__"]) + if (det$sign > 0) as.numeric(det$modulus) / 2 else NA
  }, numeric(1))
  # too few draws for a covariance: no chain is judged
  if (anyNA(log_mass) || any(!is.finite(log_mass))) {
    return(none)
  }
  best <- which.max(log_mass)
  minor <- which(log_mass < log_mass[best] - gap)
  if (length(minor) == 0L) {
    return(none)
  }
  if (length(log_mass) - length(minor) >= 2L) {
    return(list(drop = minor, restart = integer(0), from = NULL))
  }
  if (divergent[best] > 0) none else list(drop = integer(0), restart = minor, from = best)
}

# Starting values for `n` chains from the parameters-block draws of a
# one-chain stanfit, at iterations spread over its second half.
restart_inits <- function(fit, n) {
  draws <- as.array(fit)[, 1, ]
  base <- sub("\\[.*$", "", colnames(draws))
  pars <- intersect(names(fit@par_dims), unlist(parameter_block(base), use.names = FALSE))
  rows <- round(seq(nrow(draws) / 2, nrow(draws), length.out = n))
  lapply(rows, function(i) {
    values <- lapply(pars, function(p) {
      v <- unname(draws[i, base == p])
      dims <- fit@par_dims[[p]]
      if (length(dims) == 0L) v else array(v, dims)
    })
    stats::setNames(values, pars)
  })
}

# The names in the parameters blocks of the package's Stan programs
# (koh.stan, koh_basis.stan), by Stan's transform to the unconstrained scale: logit for the
# (0, 1) parameters, log for the precisions, none for the rest. Where the
# draws' variables (`names`) hold tf_u, koh_basis.stan's, tf is one of its
# transformed parameters; tf_u is taken as it is (Stan's unconstrained value
# is tf_u / linear_box$multiplier, the same factor for every chain). Where
# they hold z, koh_basis.stan samples z alone (an affine map of the rest).
parameter_block <- function(names = character()) {
  if ("z" %in% names) {
    return(list(logit = character(), log = character(), identity = "z"))
  }
  list(logit = c(if (!"tf_u" %in% names) "tf", "rho_eta", "rho_delta"),
       log = c("lambda_eta", "lambda_delta", "lambda_e", "lambda_shift"),
       identity = c("b", "gamma", "y_pred", "tf_u"))
}

# A chain's draws of the parameters block on Stan's unconstrained scale
# (parameter_block()); transformed parameters and generated quantities are
# left out.
unconstrained_draws <- function(draws) {
  base <- sub("\\[.*$", "", colnames(draws))
  block <- parameter_block(base)
  cbind(stats::qlogis(draws[, base %in% block$logit, drop = FALSE]),
        log(draws[, base %in% block$log, drop = FALSE]),
        draws[, base %in% block$identity, drop = FALSE])
}

# Tells which chains were dropped (`dropped`) or run again from the one
# chain in the main mode (`restarted`, restarted_chains()) as stuck in a
# minor mode, and which stage-2 chains were kept there (`kept`); `moved`
# (from moved_parameters()) lists the calibration parameters the minor mode
# put elsewhere.
inform_minor_modes <- function(dropped = integer(0), restarted = NULL, moved = character(),
                               kept = integer(0)) {
  if (length(dropped) > 0L || length(restarted) > 0L) {
    done <- if (length(restarted) == 0L) "dropped" else
      sprintf("run again from the draws of chain %d, which alone found the main mode", restarted$from)
    # a mode that moves the calibration can be the fixed emulator's error
    # (see kept_modes_advice()): the advice is to check it over every mode
    advice <- if (length(moved) > 0L) {
      c(stats::setNames(moved, rep("x", length(moved))),
        i = "The emulator can be right at the main mode and wrong between the modes: refit with {.code minor_modes = \"keep\"} and check it over every mode with {.fn validate_emulator}, or add runs with {.fn design_posterior}.")
    } else {
      c(i = "Keep every chain as it ran with {.code minor_modes = \"keep\"}.")
    }
    said <- sprintf("%s stuck in a minor mode (under e^-5 of the main mode's posterior mass) and %s.",
                    chains_were(if (length(restarted) == 0L) dropped else restarted$chains), done)
    cli::cli_inform(c("!" = said, advice), class = "bayesbem_message_minor_modes")
  }
  if (length(kept) > 0L) {
    cli::cli_inform(c("!" = paste0(kept_modes_said(kept), ":"),
                      stats::setNames(moved, rep("x", length(moved))), i = kept_modes_advice()),
                    class = "bayesbem_message_minor_modes")
  }
}

# What calibrate()'s message and check_convergence()'s hint say of stage-2
# chains kept in a minor mode. With the emulator fixed at stage 1, two modes
# of the calibration can have the truth between them while the emulator
# checks out at the main mode alone, so both modes need checking.
kept_modes_said <- function(kept) {
  paste(chains_were(kept), "kept in a minor mode (under e^-5 of the main mode's posterior mass)",
        "that puts the calibration parameters elsewhere")
}

kept_modes_advice <- function() {
  paste("With the emulator fixed at its stage-1 estimate such a mode can be the emulator's",
        "error between runs. Check the emulator over both modes with {.fn validate_emulator}",
        "and add runs there with {.fn design_posterior}.")
}

# "Chain 2 was", "Chains 1, 2 and 3 were"
chains_were <- function(k) {
  sprintf("Chain%s %s %s", if (length(k) > 1L) "s" else "", and_list(k),
          if (length(k) > 1L) "were" else "was")
}

# The calibration parameters that the minor mode put outside the main mode's
# 90 % interval (`minor_tf`, from minor_mode_tf()), one line each in
# physical units (every parameter scale is increasing).
moved_parameters <- function(fit, minor_tf) {
  moved <- moved_tf(minor_tf)
  if (!any(moved)) {
    return(character())
  }
  physical <- unscale_t(minor_tf, fit$data$scaling)
  k <- which(moved)
  sprintf("%s: %s in the minor mode, %s to %s (90%%) in the main mode.", fit$data$names$t[k],
          signif(physical["median", k], 3), signif(physical["lower", k], 3),
          signif(physical["upper", k], 3))
}

# The chains dropped, restarted or kept (stage 2, calibration elsewhere) as
# stuck in a minor mode, for the summary.
minor_modes_label <- function(dropped = integer(0), restarted = NULL, kept = integer(0)) {
  chains <- function(k) {
    sprintf("%s %s", if (length(k) > 1L) "chains" else "chain", paste(k, collapse = ", "))
  }
  label <- function(what, said) {
    if (length(said) == 0L) "" else sprintf("; %s (minor mode): %s", what, said)
  }
  paste0(label("dropped", if (length(dropped) > 0L) chains(dropped)),
         label("restarted", if (length(restarted) > 0L) {
           sprintf("%s from chain %d", chains(restarted$chains), restarted$from)
         }),
         label("kept", if (length(kept) > 0L) paste(chains(kept), "(calibration elsewhere)")))
}
