# An independent R transcription of the method's log density (method.md
# section 1): covariances element by element, the multivariate normal via
# chol(), and the priors with R's own density functions. Tests compare the
# Stan program against it.
reference_log_density <- function(sd, pars) {
  # predicted outputs (the paper's Appendix D) are field rows with unknown y
  sd$xf <- rbind(sd$xf, sd$x_pred)
  sd$y <- c(sd$y, pars$y_pred)
  sd$noise_weight <- c(sd$noise_weight, sd$noise_weight_pred)
  sd$n <- sd$n + sd$n_pred
  joint <- reference_joint(sd, pars)
  reference_normal(joint$z, joint$sigma) + reference_tf_prior(sd, pars$tf) +
    sum(stats::dbeta(pars$rho_eta, sd$rho_eta_a, sd$rho_eta_b, log = TRUE)) +
    sum(stats::dbeta(pars$rho_delta, sd$rho_delta_a, sd$rho_delta_b, log = TRUE)) +
    stats::dgamma(pars$lambda_eta, sd$lambda_eta_shape, sd$lambda_eta_rate, log = TRUE) +
    stats::dgamma(pars$lambda_delta, sd$lambda_delta_shape, sd$lambda_delta_rate, log = TRUE) +
    stats::dgamma(pars$lambda_e, sd$lambda_e_shape, sd$lambda_e_rate, log = TRUE) +
    sum(stats::dnorm(pars$gamma, 0, sd$gamma_sd, log = TRUE)) +
    sum(stats::dnorm(pars$b, 0, sd$b_sd, log = TRUE))
}

# log N(z | 0, sigma), via chol().
reference_normal <- function(z, sigma) {
  r <- chol(sigma)
  -0.5 * length(z) * log(2 * pi) - sum(log(diag(r))) - 0.5 * sum(backsolve(r, z, transpose = TRUE)^2)
}

# The field outputs' log density given the runs, log p(y | eta) = log p(y,
# eta) - log p(eta), at the emulator's hyperparameters in `pars` (no priors):
# what stage 2 of a modular fit conditions on.
reference_field_given_runs <- function(sd, pars) {
  joint <- reference_joint(sd, pars)
  runs <- sd$n + seq_len(sd$mt)
  reference_normal(joint$z, joint$sigma) -
    reference_normal(joint$z[runs], joint$sigma[runs, runs, drop = FALSE])
}

# The covariance `sigma` of z = (y, eta) and z less its mean, element by
# element (method.md section 1).
reference_joint <- function(sd, pars) {
  n <- sd$n
  m <- sd$mt
  N <- n + m
  u <- rbind(cbind(sd$xf, matrix(pars$tf, n, sd$q, byrow = TRUE)),
             cbind(sd$xc, sd$tc))
  beta_eta <- -4 * log(pars$rho_eta)
  beta_delta <- -4 * log(pars$rho_delta)
  sigma <- matrix(0, N, N)
  for (i in seq_len(N)) {
    for (j in seq_len(N)) {
      sigma[i, j] <- reference_eta_cov(u[i, ], u[j, ], sd, beta_eta, pars$lambda_eta)
    }
  }
  for (i in seq_len(n)) {
    for (j in seq_len(n)) {
      sigma[i, j] <- sigma[i, j] +
        exp(-sum(beta_delta * (sd$xf[i, ] - sd$xf[j, ])^2)) / pars$lambda_delta +
        (i == j) * sd$noise_weight[i] / pars$lambda_e
    }
  }
  # the emulator mean: coefficients b on the columns of [1, x, t] that
  # b_select picks, at every row (field rows at tf)
  coef <- reference_coef(sd, pars)
  emulator_mean <- vapply(seq_len(N), function(i) sum(c(1, u[i, ]) * coef), numeric(1))
  # the discrepancy terms h' gamma shift the observed field rows
  shift <- emulator_mean + c(drop(sd$h %*% pars$gamma), rep(0, N - nrow(sd$h)))
  list(sigma = sigma, z = c(sd$y, sd$eta_c) - shift)
}

# Log prior density of tf. The prior is stated on w, the physical value
# mapped to [0, 1]; tf is w on the parameter's scale (identity, log,
# reciprocal), so its density carries |dw / dtf|, here by central
# differences.
reference_tf_prior <- function(sd, tf) {
  to_physical <- function(k, u) {
    s <- sd$tf_lo[k] + sd$tf_span[k] * u
    v <- switch(sd$tf_scale[k] + 1, s, exp(s), -1 / s)
    (v - sd$tf_v_lo[k]) / sd$tf_v_span[k]
  }
  lp_tf <- 0
  for (k in seq_len(sd$q)) {
    w <- to_physical(k, tf[k])
    if (sd$tf_scale[k] > 0) {
      h <- 1e-5
      lp_tf <- lp_tf + log((to_physical(k, tf[k] + h) - to_physical(k, tf[k] - h)) / (2 * h))
    }
    if (sd$tf_is_normal[k] == 1) {
      lp_tf <- lp_tf + stats::dnorm(w, sd$tf_mu[k], sd$tf_sd[k], log = TRUE) -
        log(stats::pnorm(1, sd$tf_mu[k], sd$tf_sd[k]) - stats::pnorm(0, sd$tf_mu[k], sd$tf_sd[k]))
    }
  }
  lp_tf
}

# Emulator covariance of rows u and v = (x, t): the product kernel with the
# nugget on each factor where the factor's inputs are equal.
reference_eta_cov <- function(u, v, sd, beta_eta, lambda_eta) {
  x <- seq_len(sd$p)
  factor <- function(k) {
    exp(-sum(beta_eta[k] * (u[k] - v[k])^2)) + sd$nugget * all(u[k] == v[k])
  }
  factor(x) * factor(-x) / lambda_eta
}

random_koh_pars <- function(sd) {
  list(tf = as.array(stats::runif(sd$q)),
       y_pred = as.array(stats::rnorm(sd$n_pred)),
       rho_eta = as.array(stats::runif(sd$p + sd$q, 0.3, 0.99)),
       rho_delta = as.array(stats::runif(sd$p, 0.3, 0.99)),
       lambda_eta = stats::rgamma(1, 10, 10),
       lambda_delta = stats::rgamma(1, 10, 0.3),
       lambda_e = stats::rgamma(1, 10, 0.03),
       gamma = as.array(stats::rnorm(sd$n_h)),
       b = as.array(stats::rnorm(sd$n_b)))
}

# A compiled program of the package ("koh", whose data choose its
# likelihood, or "koh_basis") with data `sd`, without sampling, for
# log_prob().
koh_model_for <- function(sd, program = "koh") {
  utils::capture.output(suppressMessages(
    model <- rstan::sampling(bayesbem:::stanmodels[[program]], data = sd, chains = 0)
  ))
  model
}

# Stan's log density (priors included, no Jacobian) at constrained `pars`.
stan_log_density <- function(model, pars) {
  rstan::log_prob(model, unconstrain(model, pars), adjust_transform = FALSE)
}

# rstan::unconstrain_pars() of `pars` named as a fit names them: a
# precision given as a number is the program's vector of one element, and
# the parameters that koh.stan's likelihood does not sample (no elements)
# are added, as rstan asks for them all.
unconstrain <- function(model, pars) {
  dims <- model@par_dims
  for (par in intersect(names(pars), names(dims))) {
    if (length(dims[[par]]) == 1L && is.null(dim(pars[[par]]))) pars[[par]] <- as.array(pars[[par]])
  }
  empty <- names(Filter(function(d) length(d) > 0L && prod(d) == 0, dims))
  missing <- setdiff(empty, names(pars))
  rstan::unconstrain_pars(model, c(pars, stats::setNames(rep(list(numeric(0)), length(missing)),
                                                         missing)))
}

# koh_basis.stan's log density with data `sd` at its named parameters
# `pars` (tf_u, rho_delta, lambda_delta, lambda_e, gamma, phi), priors and
# tf_u's g'(u) included: it samples z (basis_z()) and adds the change of
# variables from u itself (logit for rho_delta, log for the precisions,
# logit of (phi + 1) / 2), which is taken out here.
basis_log_density <- function(model, sd, pars) {
  change <- sum(log(pars$rho_delta * (1 - pars$rho_delta))) + sum(log(pars$lambda_delta)) +
    sum(log(pars$lambda_e)) + sum(log((1 - pars$phi^2) / 4)) + sum(log(as.numeric(pars$lambda_shift)))
  rstan::log_prob(model, bayesbem:::basis_z(pars, sd), adjust_transform = FALSE) - change
}

# Stan's log density of the KOH program with data `sd` equals the R
# reference at `times` random parameter values.
expect_log_density_matches <- function(sd, times) {
  model <- koh_model_for(sd)
  for (i in seq_len(times)) {
    pars <- random_koh_pars(sd)
    testthat::expect_equal(stan_log_density(model, pars), reference_log_density(sd, pars),
                           tolerance = 1e-8)
  }
}

# Brute-force conditional of (eta(x_new, tf), delta(x_new)) given z: the
# joint covariance of (z, eta_new, delta_new) filled element by element,
# conditioned with solve(). `x_new` is on the scaled input range.
reference_conditional <- function(sd, pars, x_new) {
  n <- sd$n
  m <- sd$mt
  k <- nrow(x_new)
  tf_rows <- function(x) cbind(x, matrix(pars$tf, nrow(x), sd$q, byrow = TRUE))
  # every variable: its (x, t) row, whether it carries eta, delta, noise
  u <- rbind(tf_rows(sd$xf), cbind(sd$xc, sd$tc), tf_rows(x_new), tf_rows(x_new))
  has_eta <- c(rep(TRUE, n + m + k), rep(FALSE, k))
  has_delta <- c(rep(TRUE, n), rep(FALSE, m + k), rep(TRUE, k))
  is_field <- c(rep(TRUE, n), rep(FALSE, m + 2 * k))
  beta_eta <- -4 * log(pars$rho_eta)
  beta_delta <- -4 * log(pars$rho_delta)
  total <- n + m + 2 * k
  cov <- matrix(0, total, total)
  for (i in seq_len(total)) {
    for (j in seq_len(total)) {
      v <- 0
      if (has_eta[i] && has_eta[j]) {
        v <- v + reference_eta_cov(u[i, ], u[j, ], sd, beta_eta, pars$lambda_eta)
      }
      if (has_delta[i] && has_delta[j]) {
        xi <- u[i, seq_len(sd$p)]
        xj <- u[j, seq_len(sd$p)]
        v <- v + exp(-sum(beta_delta * (xi - xj)^2)) / pars$lambda_delta
      }
      if (i == j && is_field[i]) v <- v + sd$noise_weight[i] / pars$lambda_e
      cov[i, j] <- v
    }
  }
  train <- seq_len(n + m)
  new <- n + m + seq_len(2 * k)
  # the emulator mean of every eta variable, from [1, x, t] . coef
  coef <- reference_coef(sd, pars)
  mu <- ifelse(has_eta, drop(cbind(1, u) %*% coef), 0)
  z <- c(sd$y - drop(sd$h %*% pars$gamma), sd$eta_c) - mu[train]
  list(mean = mu[new] + drop(cov[new, train] %*% solve(cov[train, train], z)),
       cov = cov[new, new] - cov[new, train] %*% solve(cov[train, train], cov[train, new]))
}

# The emulator mean's coefficients on [1, x, t] (zero without a mean).
reference_coef <- function(sd, pars) {
  coef <- numeric(1 + sd$p + sd$q)
  for (j in seq_len(sd$n_b)) coef <- coef + sd$b_select[, j] * pars$b[j]
  coef
}

# The same parameters in the form R's prediction code takes.
as_draw_pars <- function(pars, nugget, sd) {
  list(tf = pars$tf, beta_eta = -4 * log(pars$rho_eta), beta_delta = -4 * log(pars$rho_delta),
       lambda_eta = pars$lambda_eta, lambda_delta = pars$lambda_delta,
       lambda_e = pars$lambda_e, gamma = pars$gamma, coef = reference_coef(sd, pars),
       nugget = nugget)
}

# A random grid problem: every run at every field input and at `extra`
# further inputs, rows shuffled; with `days`, the rows are periods of 20 to
# 40 days (an input `days`: the noise grows with it).
random_grid_data <- function(n = 7, runs = 5, extra = 2, days = FALSE) {
  x <- matrix(runif((n + extra) * 2), n + extra, 2, dimnames = list(NULL, c("a", "b")))
  if (days) x <- cbind(x, days = sample(20:40, n + extra, replace = TRUE))
  design <- cbind(k1 = runif(runs, 0, 3), k2 = runif(runs, 10, 20), k3 = runif(runs))
  sim <- do.call(rbind, lapply(seq_len(runs), function(r) {
    data.frame(eta = rnorm(n + extra, 5), x, t(design[r, ]))
  }))
  koh_data(data.frame(y = rnorm(n, 5), x[seq_len(n), ]), sim[sample(nrow(sim)), ])
}

# Data of two outputs, "elec" and "gas", sharing a design of `runs` runs
# over k1-k3, with random outputs: "gas" lacks the third of elec's field
# inputs (a month without a bill) and is on another scale; every run is at
# every input (and `extra` inputs beyond the field's).
random_outputs_data <- function(n = 7, runs = 6, extra = 1) {
  x <- matrix(runif((n + extra) * 2), n + extra, 2, dimnames = list(NULL, c("a", "b")))
  design <- cbind(k1 = runif(runs, 0, 3), k2 = runif(runs, 10, 20), k3 = runif(runs))
  sim <- do.call(rbind, lapply(seq_len(runs), function(r) {
    rbind(data.frame(output = "elec", eta = rnorm(n + extra, 5), x, t(design[r, ])),
          data.frame(output = "gas", eta = rnorm(n + extra, 300, 20), x, t(design[r, ])))
  }))
  gas_rows <- seq_len(n)[-3]
  field <- rbind(data.frame(output = "elec", y = rnorm(n, 5), x[seq_len(n), ]),
                 data.frame(output = "gas", y = rnorm(n - 1, 300, 20), x[gas_rows, ]))
  list(field = field, sim = sim[sample(nrow(sim)), ])
}

# An independent transcription of the basis emulator given the runs at tf
# (Higdon et al. 2008): each component's Gaussian process built element by
# element from its hyperparameters and the runs' weights, its mean
# coefficients by generalised least squares, solved with solve(); then the
# field outputs' mean and covariance, and stage 2's log density with R's own
# density functions. `kernel(a, b, beta_delta, lambda_delta)`: the
# discrepancy's covariance of two rows of inputs, by default the product
# squared-exponential kernel. `noise_cor`: the correlation of the truncated
# components and the noise between rows (by default none).
reference_basis <- function(sd, basis, pars, kernel = NULL, noise_cor = diag(sd$n), extra_cov = 0) {
  if (is.null(kernel)) kernel <- function(a, b, beta, lambda) exp(-sum(beta * (a - b)^2)) / lambda
  tc <- basis$tc
  mt <- nrow(tc)
  h <- cbind(1, tc)
  comp <- vapply(seq_along(basis$components), function(j) {
    gp <- basis$components[[j]]
    kern <- function(a, b) gp$s2 * exp(-sum(gp$beta * (a - b)^2))
    k_runs <- matrix(0, mt, mt)
    for (a in seq_len(mt)) for (c in seq_len(mt)) k_runs[a, c] <- kern(tc[a, ], tc[c, ])
    k_runs <- k_runs + diag(gp$s2 * gp$nug, mt)
    w <- basis$w[, j]
    b <- solve(t(h) %*% solve(k_runs, h), t(h) %*% solve(k_runs, w))
    k <- vapply(seq_len(mt), function(a) kern(pars$tf, tc[a, ]), numeric(1))
    c(sum(c(1, pars$tf) * b) + sum(k * solve(k_runs, w - h %*% b)),
      max(gp$s2 * (1 + gp$nug) - sum(k * solve(k_runs, k)), 0))
  }, numeric(2))
  n <- sd$n
  beta_delta <- -4 * log(pars$rho_delta)
  cov <- matrix(0, n, n)
  for (i in seq_len(n)) {
    for (j in seq_len(n)) {
      cov[i, j] <- sum(basis$B[i, ] * comp[2, ] * basis$B[j, ]) +
        kernel(sd$xf[i, ], sd$xf[j, ], beta_delta, pars$lambda_delta) +
        noise_cor[i, j] * (basis$s2r + sd$noise_weight[i] / pars$lambda_e)
    }
  }
  cov <- cov + extra_cov
  mean <- basis$mu + drop(basis$B %*% comp[1, ])
  r <- chol(cov)
  z <- sd$y - mean
  ll <- -0.5 * n * log(2 * pi) - sum(log(diag(r))) - 0.5 * sum(backsolve(r, z, transpose = TRUE)^2)
  lp <- ll + reference_tf_prior(sd, pars$tf) +
    sum(stats::dbeta(pars$rho_delta, sd$rho_delta_a, sd$rho_delta_b, log = TRUE)) +
    stats::dgamma(pars$lambda_delta, sd$lambda_delta_shape, sd$lambda_delta_rate, log = TRUE) +
    stats::dgamma(pars$lambda_e, sd$lambda_e_shape, sd$lambda_e_rate, log = TRUE)
  eta_var <- vapply(seq_len(n), function(i) sum(basis$B[i, ]^2 * comp[2, ]), numeric(1)) + basis$s2r
  list(mean = mean, cov = cov, eta_var = eta_var, lp = lp)
}

# One output's stage-2 parameters as the stage-2 programs take them: the
# precisions lambda_delta and lambda_e and koh_basis.stan's AR(1) phi
# (none without AR(1) noise) are vectors, one element per output.
stage2_pars <- function(pars) {
  pars <- pars[intersect(c("tf", "tf_u", "rho_delta", "lambda_delta", "lambda_e", "gamma", "phi",
                           "lambda_shift"), names(pars))]
  pars$phi <- pars$phi %||% numeric(0)
  pars$lambda_shift <- pars$lambda_shift %||% numeric(0)
  for (par in c("lambda_delta", "lambda_e", "phi", "lambda_shift")) pars[[par]] <- as.array(pars[[par]])
  pars
}

# The additive Hilbert-space discrepancy's covariance of two rows of
# inputs, term by term: for each input k and basis function j = 1..m, the
# spectral density of exp(-b_k d^2) / (p lambda), b_k = sqrt(beta_k^2 +
# 0.08^2), at pi j / (2 L) times
# the two sines L^-1/2 sin(pi j (x - 1/2 + L) / (2 L)).
reference_hsgp_kernel <- function(m, boundary) {
  L <- boundary / 2
  function(a, b, beta, lambda) {
    beta <- sqrt(beta^2 + 0.08^2)
    total <- 0
    for (k in seq_along(beta)) {
      for (j in seq_len(m)) {
        w <- pi * j / (2 * L)
        density <- sqrt(pi / beta[k]) * exp(-w^2 / (4 * beta[k])) / (length(beta) * lambda)
        total <- total + density * sin(w * (a[k] - 0.5 + L)) * sin(w * (b[k] - 0.5 + L)) / L
      }
    }
    total
  }
}

# The correlation matrix of AR(1) noise over rows in segments: phi^|i - j|
# within a segment, 0 across, element by element.
reference_ar1_cor <- function(phi, segments) {
  n <- length(segments)
  r <- matrix(0, n, n)
  for (i in seq_len(n)) {
    for (j in seq_len(n)) {
      if (segments[i] == segments[j]) r[i, j] <- phi^abs(i - j)
    }
  }
  r
}

# Grid data of 9 hourly field rows with a gap after the fourth (two AR(1)
# segments, `segments`), its basis emulator (99 % of the runs' variance)
# and koh_basis.stan's data for it with AR(1) noise and the additive
# discrepancy (6 sines on a box of 3 ranges).
ar1_basis_case <- function(priors = koh_priors()) {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * c(0:3, 6:10)
  d$names$period <- "time"
  basis <- bayesbem:::basis_emulator(d, variance = 0.99)
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                   b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))), basis = basis)
  sd <- bayesbem:::basis_stan_data(d, priors, emulator, bayesbem:::hsgp_design(m = 6, boundary = 3),
                                   bayesbem:::output_segments(d))
  list(data = d, segments = rep(1:2, c(4, 5)), basis = basis, sd = sd)
}
