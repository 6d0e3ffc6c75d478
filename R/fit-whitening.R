# Whitening stage 2 of the modular fit (inst/stan/koh_modular.stan). NUTS
# samples z, the parameters' unconstrained values u whitened by a Laplace
# approximation N(m, S S') of the posterior on u: u = m + S z. rstan cannot
# be given an initial mass matrix, so without this warm-up starts from the
# unit metric in u, where the scales differ twentyfold at 365 days and fan
# efficiency and equipment density are correlated; its first windows then
# take most of the leapfrog steps (bench/RESULTS.md). In z the unit metric
# is about right from the first iteration.

# The layout of u in koh_modular.stan: logit tf (q), logit rho_delta (p),
# log lambda_delta, log lambda_e, gamma (n_h).
stage2_layout <- function(stan_data) {
  c(tf = stan_data$q, rho_delta = stan_data$p, lambda_delta = 1L, lambda_e = 1L,
    gamma = stan_data$n_h)
}

# Stan's transforms of stage 2's parameters to u, for a list of their
# constrained values (an init or a draw); NA where a parameter is missing.
stage2_unconstrain <- function(values, stan_data) {
  layout <- stage2_layout(stan_data)
  transform <- list(tf = stats::qlogis, rho_delta = stats::qlogis, lambda_delta = log,
                    lambda_e = log, gamma = identity)
  unlist(lapply(names(layout), function(par) {
    v <- values[[par]]
    if (is.null(v)) rep(NA_real_, layout[[par]]) else transform[[par]](as.numeric(v))
  }), use.names = FALSE)
}

# Each chain's starting u, from calibrate()'s `init` and `init_r` as
# rstan::sampling() reads them: "random" (or NULL) draws U(-init_r, init_r)
# on the unconstrained scale, 0 or "0" starts at 0, a list (one element per
# chain) or a function (of `chain_id`, or of nothing) gives constrained
# values, and what they leave out is drawn at random.
stage2_starts <- function(init, init_r, chains, seed, stan_data) {
  d <- sum(stage2_layout(stan_data))
  init_r <- init_r %||% 2
  random <- with_seed(seed, matrix(stats::runif(d * chains, -init_r, init_r), d))
  lapply(seq_len(chains), function(k) {
    given <- if (is.null(init) || identical(init, "random")) {
      NULL
    } else if (identical(init, 0) || identical(init, "0")) {
      return(numeric(d))
    } else if (is.function(init)) {
      if ("chain_id" %in% names(formals(init))) init(chain_id = k) else init()
    } else {
      init[[k]]
    }
    u <- if (is.null(given)) rep(NA_real_, d) else stage2_unconstrain(given, stan_data)
    ifelse(is.na(u), random[, k], u)
  })
}

# The whitened stage 2: its data with u_loc and u_scale, and each chain's
# init (z). From each chain's start, a quasi-Newton search for the mode of
# the log posterior on u (Jacobian included, on the unwhitened program);
# the best mode and the curvature there give the whitening (laplace_scale());
# each chain starts at the mode its own search reached, so chains whose
# starts lie in other modes' basins still find them and minor_mode_chains()
# still sees them. A search that fails leaves its chain at its start.
whiten_stage2 <- function(model, stan_data, starts) {
  d <- length(starts[[1]])
  # rstan says that 0 chains sample nothing
  suppressMessages(utils::capture.output(
    instance <- rstan::sampling(model, data = modifyList(stan_data, unit_whitening(d)),
                                chains = 0)
  ))
  modes <- lapply(starts, function(u) climb_log_prob(instance, u))
  lp <- vapply(modes, `[[`, numeric(1), "lp")
  best <- modes[[which.max(lp)]]$u
  scale <- laplace_scale(log_prob_hessian(instance, best))
  inverse <- solve(scale)
  list(data = modifyList(stan_data, list(u_loc = best, u_scale = scale)),
       inits = lapply(modes, function(m) list(z = as.array(drop(inverse %*% (m$u - best))))))
}

# The mode of a model instance's log density reached by BFGS from `u`, and
# its log density; `u` itself (lp -Inf) when the search cannot run.
climb_log_prob <- function(instance, u) {
  lp <- function(x) {
    v <- tryCatch(rstan::log_prob(instance, x), error = function(e) -Inf)
    if (is.finite(v)) v else -1e300
  }
  grad <- function(x) {
    g <- tryCatch(rstan::grad_log_prob(instance, x), error = function(e) rep(NA_real_, length(x)))
    if (all(is.finite(g))) as.numeric(g) else numeric(length(x))
  }
  if (lp(u) <= -1e300) {
    return(list(u = u, lp = -Inf))
  }
  res <- stats::optim(u, function(x) -lp(x), function(x) -grad(x), method = "BFGS",
                      control = list(maxit = 500L, reltol = 1e-10))
  list(u = res$par, lp = -res$value)
}

# The Hessian of a model instance's log density at `u` by central
# differences of its gradient (Stan's), made symmetric; minus the identity
# (a unit whitening) where the gradient fails nearby.
log_prob_hessian <- function(instance, u, h = 1e-4) {
  d <- length(u)
  H <- vapply(seq_len(d), function(k) {
    e <- replace(numeric(d), k, h)
    tryCatch((as.numeric(rstan::grad_log_prob(instance, u + e)) -
                as.numeric(rstan::grad_log_prob(instance, u - e))) / (2 * h),
             error = function(e) rep(NA_real_, d))
  }, numeric(d))
  if (!all(is.finite(H))) -diag(d) else (H + t(H)) / 2
}

# A square root S of the Laplace covariance (-H)^-1, S = V diag(lambda)^-1/2
# from the eigen decomposition -H = V diag(lambda) V'. Curvatures below
# `min_precision` (flat or saddle directions, where the mode says little of
# the spread) are raised to it: sd at most 1 / sqrt(min_precision) = 5 on the
# unconstrained scale, the reach of Stan's random inits.
laplace_scale <- function(H, min_precision = 1 / 25) {
  e <- eigen(-H, symmetric = TRUE)
  lambda <- pmax(e$values, min_precision)
  e$vectors %*% diag(1 / sqrt(lambda), length(lambda))
}
