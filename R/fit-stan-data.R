# Every data list and starting-value list the Stan programs take:
# koh.stan's four likelihoods (joint dense and grid, stage 1, stage 2) and
# koh_basis.stan (stage 2 with the basis emulator), one output or several.

# koh.stan's likelihoods, by name: its data `likelihood`.
koh_likelihoods <- c(dense = 1L, grid = 2L, emulator = 3L, modular = 4L)

# The data block of koh.stan for one of its likelihoods: the `fields` that
# likelihood reads, and every field it does not read at size zero (one
# output, every row its row, when `output` is not among them).
koh_program_data <- function(likelihood, fields) {
  p <- fields$p
  mt <- fields$mt
  unread <- list(K = 1L, output = as.array(rep(1, fields$n)), lapack = 0L,
                 xc = matrix(0, 0, p), eta_c = numeric(0), n_pred = 0L,
                 x_pred = matrix(0, 0, p), noise_weight_pred = numeric(0),
                 n_x = 0L, eta = matrix(0, 0, mt), x_grid = matrix(0, 0, p),
                 eta_f = matrix(0, 0, mt), beta_eta_fixed = matrix(0, p + fields$q, 0),
                 lambda_eta_fixed = numeric(0), b_fixed = matrix(0, fields$n_b, 0),
                 n_max = 0L, E_f = matrix(0, 0, mt), Kx_ff = matrix(0, 0, 0),
                 Lt = matrix(0, 0, mt))
  c(list(likelihood = koh_likelihoods[[likelihood]]), fields,
    unread[setdiff(names(unread), names(fields))])
}

# koh.stan's data for a joint fit, likelihood "dense" or "grid", for given
# data and priors. `x_pred`: scaled inputs whose outputs Stan samples (the
# paper's Appendix D; dense only).
koh_stan_data <- function(data, priors, x_pred = NULL, structure = "dense",
                          call = rlang::caller_env()) {
  prior_data <- koh_prior_data(data, priors, call = call)
  field <- list(n = data$n, p = data$p, q = data$q, y = data$y,
                noise_weight = as.array(noise_weights(data)))
  if (is_grid(structure)) {
    grid <- data$grid
    return(koh_program_data("grid", c(
      field, list(mt = grid$mt, tc = grid$design, xf = field_grid_inputs(data),
                  n_x = grid$n_x, eta = grid_runs(data), x_grid = grid$x,
                  eta_f = field_runs(data), lapack = as.integer(use_lapack(call))),
      prior_data)))
  }
  if (is.null(x_pred)) x_pred <- matrix(0, 0, data$p, dimnames = list(NULL, data$names$x))
  koh_program_data("dense", c(
    field, list(mt = data$m, tc = data$tc, xf = data$xf, xc = data$xc, eta_c = data$eta,
                n_pred = nrow(x_pred), x_pred = x_pred,
                noise_weight_pred = as.array(noise_weights(data, unscale_x(x_pred, data$scaling)))),
    prior_data))
}

# The part of every program's data block that koh_prior_data.stan declares:
# the tf priors on the [0, 1] scale of physical units (checked: each names a
# parameter, its mean in the design range) with each parameter's scale for
# the change of variables (tf_prior_lpdf() in koh_functions.stan), the
# hyperpriors, the discrepancy terms and the emulator mean.
koh_prior_data <- function(data, priors, call = rlang::caller_env()) {
  t_names <- data$names$t
  unknown <- setdiff(names(priors$tf), t_names)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("Prior{?s} given for {.field {unknown}}, which {?is not a/are not} calibration parameter{?s}.",
                     i = "The calibration parameters are {.field {t_names}}."),
                   "prior", call = call)
  }
  q <- data$q
  is_normal <- mu <- numeric(q)
  sd <- rep(1, q)
  bounds <- t_bounds(data$scaling)
  for (k in seq_len(q)) {
    pr <- priors$tf[[t_names[k]]]
    if (is.null(pr) || pr$family == "uniform") next
    lo <- bounds$lower[[k]]
    hi <- bounds$upper[[k]]
    if (pr$mu < lo || pr$mu > hi) {
      abort_bayesbem(c("The prior mean of {.field {t_names[k]}} must lie in its design range [{signif(lo, 4)}, {signif(hi, 4)}].",
                       x = "It is {pr$mu}.",
                       i = "Give {.arg mu} in the parameter's physical units, or widen the simulation design."),
                     "prior", call = call)
    }
    is_normal[k] <- 1
    mu[k] <- (pr$mu - lo) / (hi - lo)
    sd[k] <- pr$sd
  }
  b_select <- mean_selection(priors, data$p, q)
  list(
    tf_is_normal = as.array(is_normal), tf_mu = as.array(mu), tf_sd = as.array(sd),
    tf_scale = as.array(match(t_scales(data$scaling), names(scale_functions)) - 1),
    tf_lo = as.array(unname(data$scaling$t_min)),
    tf_span = as.array(unname(data$scaling$t_max - data$scaling$t_min)),
    tf_v_lo = as.array(unname(bounds$lower)), tf_v_span = as.array(unname(bounds$upper - bounds$lower)),
    rho_eta_a = priors$rho_eta[1], rho_eta_b = priors$rho_eta[2],
    rho_delta_a = priors$rho_delta[1], rho_delta_b = priors$rho_delta[2],
    lambda_eta_shape = priors$lambda_eta[1],
    lambda_eta_rate = lambda_eta_rate(data, priors, b_select),
    lambda_delta_shape = priors$lambda_delta[1], lambda_delta_rate = priors$lambda_delta[2],
    lambda_e_shape = priors$lambda_e[1], lambda_e_rate = priors$lambda_e[2],
    nugget = priors$nugget,
    n_h = ncol(discrepancy_design(data)),
    h = discrepancy_design(data),
    gamma_sd = priors$gamma_sd %||% 1,
    n_b = ncol(b_select),
    b_select = b_select,
    b_sd = priors$mean_sd %||% 1
  )
}

# The rate of the emulator precision's Gamma prior. The paper's Gamma(10,
# 10) centres the emulator's variance on that of the standardised runs,
# which a zero-mean emulator must carry; the "scaled" set centres it on
# what the emulator mean leaves (equation: rate x v, v = residual sum of
# squares of the least-squares fit of the runs on the mean's columns of
# [1, x, t], over m - 1), so that v = 1 and the sets agree for a zero or
# constant mean.
lambda_eta_rate <- function(data, priors, b_select) {
  rate <- priors$lambda_eta[2]
  if (prior_set_of(priors) == "paper") {
    return(rate)
  }
  h <- cbind(1, data$xc, data$tc) %*% b_select
  resid <- if (ncol(h) == 0L) data$eta else stats::lm.fit(h, data$eta)$residuals
  rate * sum(resid^2) / (length(data$eta) - 1)
}

# Stage 1 on at most `max_inputs` of the grid inputs (evenly spaced over the
# field inputs, then the further ones): the length scales of x are learnt
# from a few dozen inputs as well as from hundreds, at a fraction of the cost.
emulator_rows <- function(grid, max_inputs = 60L) {
  if (grid$n_x <= max_inputs) {
    return(seq_len(grid$n_x))
  }
  unique(round(seq(1, grid$n_x, length.out = max_inputs)))
}

# koh.stan's data for stage 1 (likelihood "emulator"): the grid
# likelihood's runs on emulator_rows() of the grid inputs (the field
# outputs are not read).
emulator_stan_data <- function(data, priors) {
  stan_data <- koh_stan_data(data, priors, structure = "grid")
  rows <- emulator_rows(data$grid)
  stan_data$likelihood <- koh_likelihoods[["emulator"]]
  stan_data$n_x <- length(rows)
  stan_data$eta <- stan_data$eta[rows, , drop = FALSE]
  stan_data$x_grid <- stan_data$x_grid[rows, , drop = FALSE]
  stan_data$eta_f <- stan_data$eta_f[0, , drop = FALSE]
  stan_data
}

# The data every stage-2 program takes, for one output or several (`data` a
# bayesbem_data or bayesbem_outputs object): the field data stacked by
# output (each on its own scaling), the runs' design they share, the
# priors, the discrepancy terms of each output in its own columns (zero in
# the others' rows).
stage2_stan_data <- function(data, priors) {
  outputs <- output_data(data)
  first <- outputs[[1]]
  prior <- koh_prior_data(first, priors)
  prior$h <- block_diagonal(lapply(outputs, discrepancy_design))
  prior$n_h <- ncol(prior$h)
  c(list(n = sum(vapply(outputs, `[[`, integer(1), "n")), mt = first$grid$mt, p = first$p,
         q = first$q, y = unlist(lapply(outputs, `[[`, "y")),
         xf = do.call(rbind, lapply(outputs, field_grid_inputs)),
         tc = first$grid$design, K = length(outputs),
         output = as.array(rep(seq_along(outputs), vapply(outputs, `[[`, integer(1), "n"))),
         noise_weight = as.array(unlist(lapply(outputs, noise_weights))),
         lapack = as.integer(use_lapack())),
    prior)
}

# The one-output data sets of a data set (one output's: itself), and their
# stage-1 emulators in the same order: several outputs' data dispatch here.
output_data <- function(data) UseMethod("output_data")

output_data.default <- function(data) list(data)

output_data.bayesbem_outputs <- function(data) data$outputs

# The AR(1) noise's segments of each output's field rows (field_segments()),
# by output: what calibrate() resolves once and a fit keeps.
output_segments <- function(data, call = rlang::caller_env()) {
  lapply(output_data(data), field_segments, call = call)
}

output_emulators <- function(data, emulator) UseMethod("output_emulators")

output_emulators.default <- function(data, emulator) list(emulator)

output_emulators.bayesbem_outputs <- function(data, emulator) emulator

# One column per output of a stage-1 emulator's element (beta_eta, b).
emulator_columns <- function(emulators, name) {
  matrix(unlist(lapply(emulators, `[[`, name)), ncol = length(emulators))
}

# The matrices of `blocks` on the diagonal of one matrix, zero elsewhere.
block_diagonal <- function(blocks) {
  rows <- vapply(blocks, nrow, integer(1))
  cols <- vapply(blocks, ncol, integer(1))
  out <- matrix(0, sum(rows), sum(cols))
  for (k in seq_along(blocks)) {
    out[sum(rows[seq_len(k - 1L)]) + seq_len(rows[k]),
        sum(cols[seq_len(k - 1L)]) + seq_len(cols[k])] <- blocks[[k]]
  }
  out
}

# koh.stan's data for stage 2 (likelihood "modular"): stage2_stan_data(),
# the separable stage-1 emulators, one column each, and each one's pieces,
# stacked by output: the runs at the field inputs less the emulator mean,
# the field block of Kx (its first columns), the Cholesky factor of Kt.
modular_stan_data <- function(data, priors, emulator) {
  emulators <- output_emulators(data, emulator)
  pieces <- Map(modular_pieces, output_data(data), emulators, MoreArgs = list(priors = priors))
  kx <- lapply(pieces, `[[`, "Kx_ff")
  n_max <- max(vapply(kx, nrow, integer(1)))
  koh_program_data("modular", c(
    stage2_stan_data(data, priors),
    list(beta_eta_fixed = emulator_columns(emulators, "beta_eta"),
         lambda_eta_fixed = as.array(vapply(emulators, `[[`, numeric(1), "lambda_eta")),
         b_fixed = emulator_columns(emulators, "b"),
         n_max = n_max, E_f = do.call(rbind, lapply(pieces, `[[`, "E_f")),
         Kx_ff = do.call(rbind, lapply(kx, function(k) cbind(k, matrix(0, nrow(k), n_max - ncol(k))))),
         Lt = do.call(rbind, lapply(pieces, `[[`, "Lt")))))
}

# One output's pieces of modular_stan_data().
modular_pieces <- function(data, emulator, priors) {
  grid <- data$grid
  p <- data$p
  xf <- field_grid_inputs(data)
  coef <- drop(mean_selection(priors, p, data$q) %*% emulator$b)
  if (length(coef) == 0L) coef <- numeric(1 + p + data$q)
  beta_x <- emulator$beta_eta[seq_len(p)]
  beta_t <- emulator$beta_eta[-seq_len(p)]
  E <- field_runs(data)
  kt <- jittered_cor(pair_geometry(grid$design, grid$design), beta_t, priors$nugget)
  list(E_f = E - grid_mean(xf, grid$design, coef),
       Kx_ff = jittered_cor(pair_geometry(xf, xf), beta_x, priors$nugget),
       Lt = t(chol(kt)))
}

# Starting values given as a list per chain (rstan::sampling()'s `init`), as
# the Stan programs take them: the precisions are vectors (one element per
# output, or the emulator's one), and a basis fit samples tf as tf_u
# (basis_inits()).
stan_inits <- function(init, emulator) {
  if (emulator == "basis") init <- basis_inits(init)
  if (!is.list(init)) {
    return(init)
  }
  lapply(init, function(chain) {
    for (par in intersect(c("lambda_eta", "lambda_delta", "lambda_e", "lambda_shift"), names(chain))) {
      chain[[par]] <- as.array(chain[[par]])
    }
    chain
  })
}

# The data of koh_basis.stan: stage 2's common data (stage2_stan_data())
# and the pieces of each output's basis emulator (`emulator$basis`),
# stacked by output: its rows and its components a block of the bases `B`;
# with an hsgp_design() `hsgp`, the additive discrepancy's (hsgp_stan_data()),
# with AR(1) noise over each output's `segments` (output_segments()) and a
# shift per month of each output's rows' `shifts` (field_months()) when given.
basis_stan_data <- function(data, priors, emulator, hsgp = NULL, segments = NULL, shifts = NULL) {
  bases <- lapply(output_emulators(data, emulator), `[[`, "basis")
  gps <- unlist(lapply(bases, `[[`, "components"), recursive = FALSE)
  mt <- nrow(bases[[1]]$tc)
  field <- function(name, size) matrix(vapply(gps, `[[`, numeric(size), name), ncol = length(gps))
  q <- ncol(bases[[1]]$tc)
  sd <- c(stage2_stan_data(data, priors),
          list(tf_edge = linear_box$edge, tf_multiplier = linear_box$multiplier,
               pc = length(gps),
               pc_output = as.array(rep(seq_along(bases), vapply(bases, function(b) ncol(b$B), integer(1)))),
               mu_f = unlist(lapply(bases, `[[`, "mu")), B = block_diagonal(lapply(bases, `[[`, "B")),
               s2r = as.array(vapply(bases, `[[`, numeric(1), "s2r")),
               w_coef = field("b", q + 1), w_beta = field("beta", q),
               w_s2 = as.array(vapply(gps, `[[`, numeric(1), "s2")),
               w_nug = as.array(vapply(gps, `[[`, numeric(1), "nug")),
               w_alpha = field("alpha", mt), w_Ki = do.call(rbind, lapply(gps, `[[`, "ki"))))
  sd <- hsgp_stan_data(sd, hsgp, segments, shifts)
  sd[c("lambda_shift_shape", "lambda_shift_rate")] <- as.list(shift_prior(priors))
  # the sampler's z is u itself until laplace_map() sets the map
  n_u <- sum(basis_u_sizes(sd))
  c(sd, list(n_u = n_u, u_offset = as.array(numeric(n_u)), u_scale = diag(n_u)))
}

# koh_basis.stan's data of the additive Hilbert-space discrepancy added to
# its data `sd`: the frequencies, and each output's Gram matrix of Z_k =
# [B_k, Phi_k, M_k, y_k - mu_f_k, h_k] on the diagonal of `gram`, the only
# use the likelihood makes of the rows (M_k the indicators of the months of
# all outputs' `shifts`, none without); with AR(1) noise (`segments`, each
# output's noise_segments()), its ar1_grams() on the diagonals of
# `gram_lag` and `gram_end`. None (hsgp = 0) when `design` is NULL.
hsgp_stan_data <- function(sd, design, segments = NULL, shifts = NULL) {
  none <- list(ar = 0L, gram_lag = matrix(0, 0, 0), gram_end = matrix(0, 0, 0),
               n_seg = numeric(0))
  if (is.null(design)) {
    return(c(sd, list(hsgp = 0L, m = 0L, omega = numeric(0), n_shift = 0L, n_z = 0L,
                      gram = matrix(0, 0, 0)), none))
  }
  months <- sort(unique(unlist(shifts)))
  z <- lapply(seq_len(sd$K), function(k) {
    rows <- sd$output == k
    hsgp_columns(sd$B[rows, sd$pc_output == k, drop = FALSE], sd$xf[rows, , drop = FALSE],
                 sd$y[rows] - sd$mu_f[rows], sd$h[rows, , drop = FALSE], design,
                 if (!is.null(shifts)) shift_columns(shifts[[k]], months))
  })
  gram <- block_diagonal(lapply(z, crossprod))
  out <- c(sd, list(hsgp = 1L, m = design$m, omega = as.array(design$omega),
                    n_shift = length(months), n_z = nrow(gram), gram = gram))
  if (is.null(segments)) {
    return(c(out, none))
  }
  ar <- Map(ar1_grams, z, segments)
  c(out, list(ar = 1L, gram_lag = block_diagonal(lapply(ar, `[[`, "lag")),
              gram_end = block_diagonal(lapply(ar, `[[`, "end")),
              n_seg = as.array(vapply(ar, `[[`, numeric(1), "segments"))))
}

# The scale koh_basis.stan samples tf on, passed to it as data: `edge`, the
# width a of g's exponential tails (linear_box_lp(), linear_box_inverse()),
# and `multiplier`, the unit of tf_u for Stan (the logit's scale at tf = 1/2,
# so that NUTS's first, unit metric fits;
# inst/notes/decisions/F5-a-linear-scale-for-tf-in.md).
linear_box <- list(edge = 0.05, multiplier = 0.25)

# Starting values given for tf (a list per chain, as rstan::sampling()
# takes them) as koh_basis.stan samples it: tf_u = g^-1(tf). Other forms of
# `init` ("random", 0, a function) are rstan's.
basis_inits <- function(init) {
  if (!is.list(init)) {
    return(init)
  }
  lapply(init, function(chain) {
    if (is.null(chain$tf)) {
      return(chain)
    }
    c(chain[names(chain) != "tf"], list(tf_u = as.array(linear_box_inverse(chain$tf))))
  })
}

# The named parameters koh_basis.stan builds from u, in u's order, and the
# elements of each (its data `sd`).
basis_u_sizes <- function(sd) {
  c(tf_u = sd$q, rho_delta = sd$p * sd$K, lambda_delta = sd$K, lambda_e = sd$K, gamma = sd$n_h,
    phi = sd$ar * sd$K, lambda_shift = (sd$n_shift > 0) * sd$K)
}

# koh_basis.stan's z for values of its named parameters (a list as one
# chain's starting values: tf_u, rho_delta, lambda_delta, lambda_e, gamma,
# phi, lambda_shift): their unconstrained values u, in the program's order and by its
# transforms, then z = u_scale^-1 (u - u_offset). A parameter not given
# starts where Stan starts one, u ~ U(-2, 2).
basis_z <- function(values, sd) {
  size <- basis_u_sizes(sd)
  to_u <- list(tf_u = function(v) v / sd$tf_multiplier, rho_delta = stats::qlogis, lambda_delta = log,
               lambda_e = log, gamma = identity, phi = function(v) stats::qlogis((v + 1) / 2),
               lambda_shift = log)
  u <- unlist(lapply(names(size), function(par) {
    v <- values[[par]]
    if (is.null(v)) stats::runif(size[[par]], -2, 2) else to_u[[par]](as.numeric(v))
  }))
  as.array(solve(sd$u_scale, u - sd$u_offset))
}

# u = g^-1(tf) for linear_box_lp() of koh_basis.stan, g(u) = a (log(1 +
# e^(u / a)) - log(1 + e^((u - 1) / a))): with y = e^(u / a), e^(g / a) =
# (1 + y) / (1 + e^(-1 / a) y), so y = (e^(tf / a) - 1) / (1 - e^((tf - 1) / a)).
linear_box_inverse <- function(tf, a = linear_box$edge) {
  a * (log(expm1(tf / a)) - log(-expm1((tf - 1) / a)))
}
