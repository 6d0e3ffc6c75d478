# Running the NUTS chains of calibrate(): one chain per R process, a progress
# bar over all of them instead of Stan's per-chain iteration lines, and
# rstan's own diagnostic warnings left to check_convergence().

# Runs `chains` chains of `model` with rstan::sampling(), at most `cores` at a
# time. Chain k is rstan's `chain_id = k` under the same seed, so the draws
# are those of one rstan::sampling(chains = chains, seed = seed) call. Where R
# can fork (Linux, macOS), each chain runs in a forked process that writes
# Stan's iteration lines to a log file, and the parent reads the logs to move
# a cli progress bar; elsewhere the chains run one after another and the bar
# moves per chain. `args` are further rstan::sampling() arguments. A chain
# that cannot start calls `on_failure(messages)` with Stan's last lines.
# With `start_at_mode` (and no `init` given), each chain starts at the mode
# reached from its own random start (mode_start()), and koh_basis.stan
# samples through the Laplace approximation at a mode (laplace_map()).
sample_chains <- function(model, stan_data, label, chains, iter, warmup, seed, cores, control,
                          args, progress, on_failure, minor_modes = "keep", keep_moved = FALSE,
                          start_at_mode = FALSE, call = rlang::caller_env()) {
  args$refresh <- args$refresh %||% max(1L, iter %/% 50L)
  if (!is.null(stan_data$u_scale)) {
    if (start_at_mode) stan_data <- laplace_map(model, stan_data, seed)
    if (is.list(args$init)) {
      args$init <- with_seed(seed, lapply(args$init, function(v) list(z = basis_z(v, stan_data))))
    }
  }
  # Runs the chains `ids`, each from its element of `init` when that is a list
  # (one element per chain), behind one progress bar; their stanfits.
  run_chains <- function(ids, label, init = args$init) {
    run <- function(j, log) {
      if (is.list(init)) args$init <- init[j]
      if (is.null(init) && start_at_mode) args$init <- mode_start(model, stan_data, seed, ids[j])
      run_chain(c(list(model, data = stan_data, chains = 1L, chain_id = ids[j], iter = iter,
                       warmup = warmup, seed = seed, cores = 1L, control = control), args), log)
    }
    n <- length(ids)
    logs <- tempfile(sprintf("bayesbem-chain%d-", ids), fileext = ".txt")
    on.exit(unlink(logs), add = TRUE)
    bar <- if (progress) {
      cli::cli_progress_bar(label, total = n * iter, clear = FALSE, .envir = environment())
    }
    # cli closes a bar that reaches its total, so it gets there only when done
    tick <- function() {
      if (progress) {
        cli::cli_progress_update(id = bar, set = min(sum(chain_progress(logs, iter)), n * iter - 1))
      }
    }
    results <- if (can_fork()) fork_chains(run, n, cores, logs, tick) else
      lapply(seq_len(n), function(j) {
        result <- try(run(j, logs[j]), silent = TRUE)
        tick()
        result
      })
    if (progress) cli::cli_progress_done(id = bar)
    collect_chains(results, ids, on_failure, call)
  }
  fits <- run_chains(seq_len(chains), label)
  modes <- list(drop = integer(0), restart = integer(0), kept = integer(0))
  if (minor_modes == "drop") {
    modes <- settle_minor_modes(chain_draws(fits), chain_divergences(fits), keep_moved)
    if (length(modes$restart) > 0L) {
      fits[modes$restart] <- run_chains(
        modes$restart, sprintf("Restarting %d chain%s from chain %d", length(modes$restart),
                               if (length(modes$restart) > 1L) "s" else "", modes$from),
        restart_inits(fits[[modes$from]], length(modes$restart))
      )
    }
  }
  structure(rstan::sflist2stanfit(fits[setdiff(seq_along(fits), modes$drop)]),
            dropped = modes$drop, restarted = modes$restart, restarted_from = modes$from,
            kept_moved = modes$kept, minor_tf = modes$minor_tf)
}

# The affine map koh_basis.stan samples through, u = u_offset + u_scale z,
# set in its data `stan_data` (which hold the identity): the Laplace
# approximation at the highest of the modes BFGS reaches from
# basis_starts(), u_scale u_scale' the inverse of the log
# density's curvature there, so that the sampler's first, unit metric on z
# is about the posterior's covariance.
# Why: at 8,760 hours the noise precision and phi are known to about
# 1 / sqrt(n) and the discrepancy's length scales to about 1 (a condition
# number of 30,000 on u), rstan takes no initial metric, and warm-up on the
# unit metric ran at the maximum tree depth (bench/results/year-hours.md).
# Directions along which the density does not curve down keep unit
# scale, none is wider than 10; the identity stays where no mode is found.
laplace_map <- function(model, stan_data, seed) {
  instance <- stan_instance(model, stan_data)
  n <- stan_data$n_u
  climb <- highest_mode(instance, basis_starts(instance, stan_data, seed %% 1e8))
  hessian <- if (is.finite(climb$lp)) log_prob_hessian(instance, climb$u)
  if (is.null(hessian) || !all(is.finite(hessian))) {
    return(stan_data)
  }
  curvature <- eigen(-hessian, symmetric = TRUE)
  precision <- ifelse(curvature$values > 0, pmax(curvature$values, 0.01), 1)
  stan_data$u_offset <- as.array(climb$u)
  stan_data$u_scale <- curvature$vectors %*% diag(1 / sqrt(precision), n)
  stan_data
}

# The Hessian of a model instance's log density (Jacobian included) at `u`,
# by central differences of its gradient, symmetrised; NA where a gradient
# fails.
log_prob_hessian <- function(instance, u, h = 1e-4) {
  gradient <- function(x) {
    tryCatch(as.numeric(rstan::grad_log_prob(instance, x)), error = function(e) rep(NA, length(x)))
  }
  hessian <- vapply(seq_along(u), function(k) {
    e <- replace(numeric(length(u)), k, h)
    (gradient(u + e) - gradient(u - e)) / (2 * h)
  }, numeric(length(u)))
  (hessian + t(hessian)) / 2
}

# A chain's start (rstan::sampling()'s `init`) at the highest of the modes
# that BFGS reaches from the chain's own `mode_starts` random starts, drawn
# as Stan draws its inits (U(-2, 2) on the unconstrained scale), Jacobian
# included (highest_mode()); "random" where no search can start. Why: with
# thousands of rows the posterior is narrow, and from a random start the
# first warm-up iterations, on the unit metric, run at the maximum tree
# depth until they reach it (bench/results/year-hours.md).
mode_start <- function(model, stan_data, seed, chain) {
  instance <- stan_instance(model, stan_data)
  climb <- highest_mode(instance, random_starts(instance, mode_starts, seed %% 1e8 + chain))
  if (!is.finite(climb$lp)) {
    return("random")
  }
  list(lapply(rstan::constrain_pars(instance, climb$u), as.array))
}

# Random starts of each mode search of a fit with thousands of rows. One
# is not enough: an additive discrepancy with a short length scale in an
# input can mimic a parameter's effect (the equipment schedule, by
# `daytype_hour`), and BFGS's first steps often fly into such a mode, a
# local one far below the mode near the truth
# (inst/notes/decisions/F3-stage-2-from-random-inits-with.md).
mode_starts <- 8L

# The starts of laplace_map()'s search on koh_basis.stan's u (z = u while
# the map is the identity): `mode_starts` random ones (random_starts()) and
# as many again from a discrepancy small and smooth, each rho_delta at
# inv_logit(3) = 0.95 (length scales of 1.5 input ranges) and
# lambda_delta at e^3, the rest as drawn. Why: from random length scales,
# some input's is short in nearly every start, and the climb can end where
# that input's discrepancy mimics a parameter; from a simulator that
# explains the data first, it reaches the mode near the truth
# (inst/notes/decisions/F3-stage-2-from-random-inits-with.md).
basis_starts <- function(instance, stan_data, seed) {
  random <- random_starts(instance, mode_starts, seed)
  sizes <- basis_u_sizes(stan_data)
  smooth <- random
  smooth[rep(names(sizes), sizes) %in% c("rho_delta", "lambda_delta"), ] <- 3
  cbind(random, smooth)
}

# The draws of each chain's stanfit, iterations x chains x variables.
chain_draws <- function(fits) {
  first <- as.array(fits[[1]])
  draws <- array(0, replace(dim(first), 2L, length(fits)), list(NULL, NULL, dimnames(first)[[3]]))
  for (k in seq_along(fits)) draws[, k, ] <- as.array(fits[[k]])[, 1, ]
  draws
}

# Divergent transitions after warmup, per chain.
chain_divergences <- function(fits) {
  vapply(fits, function(fit) {
    sum(rstan::get_sampler_params(fit, inc_warmup = FALSE)[[1]][, "divergent__"])
  }, numeric(1))
}

# Runs `run(k, log)` for each chain in forked processes, `cores` at a time,
# calling `tick()` about four times a second; the results in chain order
# (a try-error for a chain whose process failed).
fork_chains <- function(run, chains, cores, logs, tick) {
  results <- vector("list", chains)
  pending <- seq_len(chains)
  running <- list()
  while (length(pending) > 0L || length(running) > 0L) {
    while (length(running) < cores && length(pending) > 0L) {
      k <- pending[1]
      pending <- pending[-1]
      job <- parallel::mcparallel(run(k, logs[k]), silent = TRUE)
      running[[as.character(job$pid)]] <- list(job = job, chain = k)
    }
    done <- parallel::mccollect(lapply(running, `[[`, "job"), wait = FALSE, timeout = 0.25)
    for (pid in names(done)) {
      results[running[[pid]]$chain] <- list(done[[pid]] %||% try_error("the chain's process died"))
      running[[pid]] <- NULL
    }
    tick()
  }
  results
}

can_fork <- function() .Platform$OS.type == "unix"

try_error <- function(message) {
  structure(message, class = "try-error", condition = simpleError(message))
}

# One chain with its console output in `log`. rstan's sampler warnings
# (divergences, tree depth, E-BFMI, R-hat, ESS) are dropped, since
# check_convergence() reports each of them with a class; any other warning
# is kept to be raised again in the calling process.
run_chain <- function(args, log) {
  con <- file(log, open = "wt")
  sink(con)
  sink(con, type = "message")
  on.exit({
    sink(type = "message")
    sink()
    close(con)
  })
  kept <- list()
  fit <- withCallingHandlers(do.call(rstan::sampling, args), warning = function(w) {
    if (!from_rstan_diagnostics()) kept[[length(kept) + 1L]] <<- w
    invokeRestart("muffleWarning")
  })
  messages <- if (fit@mode != 0L) utils::tail(readLines(log, warn = FALSE), 5L)
  list(fit = fit, warnings = kept, messages = messages)
}

# Whether the warning being handled was raised by rstan's end-of-sampling
# diagnostics: told by the function that raised it (on the call stack), not
# by the wording of its message.
from_rstan_diagnostics <- function() {
  diagnostics <- utils::getFromNamespace("throw_sampler_warnings", "rstan")
  frames <- seq_len(sys.nframe())
  any(vapply(frames, function(i) identical(sys.function(i), diagnostics), logical(1)))
}

# Iterations each chain has reported in its log (all of them once the chain
# has finished, which its last line does not always say).
chain_progress <- function(logs, iter) {
  vapply(logs, function(log) {
    if (!file.exists(log)) {
      return(0)
    }
    lines <- readLines(log, warn = FALSE)
    if (any(grepl("Elapsed Time", lines, fixed = TRUE))) {
      return(iter)
    }
    done <- regmatches(lines, regexpr("Iteration: *[0-9]+", lines))
    if (length(done) == 0L) 0 else as.numeric(sub("Iteration: *", "", done[length(done)]))
  }, numeric(1), USE.NAMES = FALSE)
}

# The stanfits of the chains `ids`; a chain whose process failed is an error, one
# that could not start (stanfit mode != 0) goes to `on_failure()`. Warnings
# kept by run_chain() are raised here.
collect_chains <- function(results, ids, on_failure, call) {
  failed <- which(vapply(results, inherits, logical(1), "try-error"))
  if (length(failed) > 0L) {
    abort_bayesbem(c("Chain {ids[failed[1]]} failed.",
                     x = conditionMessage(attr(results[[failed[1]]], "condition"))),
                   "sampling", call = call)
  }
  for (result in results) lapply(result$warnings, warning)
  fits <- lapply(results, `[[`, "fit")
  started <- vapply(fits, function(f) f@mode == 0L, logical(1))
  if (!all(started)) {
    on_failure(results[[which(!started)[1]]]$messages)
  }
  fits
}

# Messages and labels about chains in minor modes, for calibrate() and the
# summary.

# The chains sample_chains() ran again from the draws of the one chain in the
# main mode: `chains` and `from`; NULL when none was.
restarted_chains <- function(stanfit) {
  if (length(attr(stanfit, "restarted")) > 0L) {
    list(chains = attr(stanfit, "restarted"), from = attr(stanfit, "restarted_from"))
  }
}

# The number of chains whose draws a fit holds.
kept_chains <- function(fit) fit$settings$chains - length(fit$settings$dropped)
