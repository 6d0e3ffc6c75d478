# A calibration of one output or several. `draws`: the Stan program's
# draws as a posterior draws_array on the Stan scale (the calibration
# parameters on [0, 1]), named once: shared parameters as the program names
# them, each output's own as a one-output program does, prefixed
# "<output>:" on several outputs (output_draw_names()). `sampler`: what the
# diagnostics read of the sampler (each chain's sampler parameters, warm-up
# included, and its times). `inits`: each chain's starting values. On
# several outputs, `outputs` holds each output's view (output_view()).
new_bayesbem_fit <- function(draws, sampler, inits, data, priors, settings, predict_at = NULL,
                             emulator = NULL, outputs = NULL) {
  structure(list(draws = draws, sampler = sampler, inits = inits, data = data, priors = priors,
                 settings = settings, predict_at = predict_at, emulator = emulator,
                 outputs = outputs),
            class = "bayesbem_fit")
}

# A fit from the stanfit calibrate() sampled: its draws (a modular fit's
# with its fixed emulator, with_fixed_emulator()), the variables named by
# output (output_draw_names()), the sampler's diagnostics and the chains'
# starting values.
stanfit_fit <- function(stanfit, data, priors, settings, predict_at = NULL, emulator = NULL) {
  draws <- posterior::as_draws_array(as.array(stanfit))
  if (isTRUE(settings$modular)) draws <- with_fixed_emulator(draws, data, emulator)
  posterior::variables(draws) <- output_draw_names(posterior::variables(draws), data, emulator)
  sampler <- list(params = rstan::get_sampler_params(stanfit, inc_warmup = TRUE),
                  elapsed = rstan::get_elapsed_time(stanfit))
  # each chain's starting values of what it samples (none of what has no elements)
  inits <- lapply(rstan::get_inits(stanfit), function(chain) Filter(length, chain))
  new_bayesbem_fit(draws, sampler, inits, data, priors, settings,
                   predict_at = predict_at, emulator = emulator)
}

# A stage-2 fit's draws with the emulator of each output held fixed at
# stage 1 (`emulator`, by output), a variable whose every draw is the same,
# before lp__: named as a joint fit's sampled ones, output k's beta_eta and
# b its block of p + q and of n_b elements, its lambda_eta element k.
with_fixed_emulator <- function(draws, data, emulator) {
  emulators <- output_emulators(data, emulator)
  values <- lapply(c("beta_eta", "lambda_eta", "b"), function(par) {
    v <- as.vector(emulator_columns(emulators, par))
    stats::setNames(v, sprintf("%s[%d]", par, seq_along(v)))
  })
  values <- unlist(values)
  size <- dim(draws)[1:2]
  fixed <- posterior::as_draws_array(array(rep(values, each = prod(size)), c(size, length(values)),
                                           list(NULL, NULL, names(values))))
  sampled <- setdiff(posterior::variables(draws), "lp__")
  posterior::bind_draws(posterior::subset_draws(draws, variable = sampled), fixed,
                        posterior::subset_draws(draws, variable = "lp__"), along = "variable")
}

# Draws (rows, chain after chain) of the elements (columns) of one Stan
# parameter, on the Stan scale: what rstan's as.matrix(stanfit, pars = par)
# gives.
stan_draws <- function(fit, par) {
  d <- posterior::as_draws_matrix(posterior::subset_draws(fit$draws, variable = par))
  array(as.vector(d), dim(d), list(NULL, posterior::variables(d)))
}

# Each chain's sampler parameters after warm-up (divergent__, treedepth__,
# energy__, ...), as rstan::get_sampler_params(inc_warmup = FALSE) gives them.
sampler_params <- function(fit) {
  warmup <- fit$settings$warmup
  lapply(fit$sampler$params, function(s) s[-seq_len(warmup), , drop = FALSE])
}

# The sampler's problems in a fit (stage 2 of a modular fit, whose stage 1
# is a mode search).
fit_sampler_diagnostics <- function(fit) {
  sampler_diagnostics(sampler_params(fit), fit$settings$control$max_treedepth %||% 10)
}

# Divergent transitions, tree-depth hits and each chain's E-BFMI from the
# chains' sampler parameters after warm-up.
sampler_diagnostics <- function(sp, max_td) {
  list(divergent = sum(vapply(sp, function(s) sum(s[, "divergent__"]), numeric(1))),
       treedepth_hits = sum(vapply(sp, function(s) sum(s[, "treedepth__"] >= max_td), numeric(1))),
       max_treedepth = max_td,
       ebfmi = vapply(sp, function(s) {
         e <- s[, "energy__"]
         sum(diff(e)^2) / sum((e - mean(e))^2)
       }, numeric(1)))
}

# The variables a fit holds fixed rather than samples: a modular fit's
# emulator hyperparameters, at their stage-1 mode.
fixed_variables <- function(fit) {
  if (is.null(fit$emulator)) character() else emulator_variables(fit)
}

# The names of the emulator's hyperparameters in the convergence table: its
# correlation parameters, variance and mean coefficients. None on several
# outputs: such a fit is modular, its emulators fixed at stage 1.
emulator_variables <- function(fit) UseMethod("emulator_variables")

emulator_variables.bayesbem_fit_outputs <- function(fit) character()

emulator_variables.bayesbem_fit <- function(fit) {
  names <- emulator_draw_names(fit$data, mean_term_names(fit$priors, fit$data))
  c(names$beta_eta, "lambda_eta", names$b)
}

# Names of the emulator's draws: its correlation parameter per input and
# calibration parameter, and its mean's coefficients.
emulator_draw_names <- function(d, b_names = character()) {
  list(beta_eta = sprintf("beta_eta[%s]", c(d$names$x, d$names$t)),
       b = sprintf("b[%s]", b_names))
}

# The terms of the emulator mean: "intercept" and the names of the inputs
# and parameters it is linear in.
mean_term_names <- function(priors, data) {
  all <- c("intercept", data$names$x, data$names$t)
  all[rowSums(mean_selection(priors, data$p, data$q)) > 0]
}

# The elements of output k among a K-output program's parameters, and the
# parameters that are one number per output (scalars in a one-output fit).
output_elements <- function(k, p, q, n_b, n_h) {
  block <- function(size) (k - 1L) * size + seq_len(size)
  list(elements = list(rho_delta = block(p), beta_delta = block(p), beta_eta = block(p + q),
                       b = block(n_b), lambda_delta = k, lambda_e = k, lambda_eta = k, phi = k,
                       lambda_shift = k, gamma = sum(n_h[seq_len(k - 1L)]) + seq_len(n_h[k])),
       scalars = c("lambda_delta", "lambda_e", "lambda_eta", "phi", "lambda_shift"))
}

# output_elements() of each output of a modular fit's data, by output.
output_parts <- function(data, emulator) {
  outputs <- output_data(data)
  emulators <- output_emulators(data, emulator)
  n_h <- vapply(outputs, function(d) ncol(discrepancy_design(d)), integer(1))
  first <- outputs[[1]]
  stats::setNames(lapply(seq_along(outputs), function(k) {
    output_elements(k, first$p, first$q, length(emulators[[k]]$b), n_h)
  }), names(outputs))
}

# The Stan programs' variable names as the fit keeps them: each output's
# elements of the K-output parameters named as a one-output fit names them
# (element j of those kept is `par[j]`, a number per output `par`, as a
# joint fit's precisions, vectors of one element in Stan), prefixed
# "<output>:" on several outputs; the shared ones (tf, lp__) as they are,
# and elements the draws lack (a likelihood's unsampled ones) skipped.
output_draw_names <- function(variables, data, emulator) {
  parts <- output_parts(data, emulator)
  several <- inherits(data, "bayesbem_outputs")
  for (k in names(parts) %||% "") {
    part <- parts[[if (several) k else 1L]]
    for (par in names(part$elements)) {
      at <- match(sprintf("%s[%d]", par, part$elements[[par]]), variables)
      name <- if (par %in% part$scalars) rep(par, length(at)) else sprintf("%s[%d]", par, seq_along(at))
      if (several) name <- paste0(k, ":", name)
      variables[at[!is.na(at)]] <- name[!is.na(at)]
    }
  }
  variables
}

# Whether a fit's (or a spec's) noise is AR(1) over consecutive rows.
is_ar1 <- function(settings) identical(settings$noise_correlation, "ar1")

# The AR(1) noise's segments of a one-output fit's field rows, as
# calibrate() resolved them (fits made before they were kept: found again).
fit_segments <- function(fit) {
  if (!is_ar1(fit$settings)) {
    return(NULL)
  }
  fit$settings$segments[[1]] %||% field_segments(fit$data)
}

# Whether a fit's (or a spec's) noise has a shift per month.
has_shifts <- function(settings) identical(settings$noise_shift, "month")

# The months of a one-output fit's field rows, as calibrate() resolved them
# (NULL without a shift per month).
fit_shifts <- function(fit) {
  if (has_shifts(fit$settings)) fit$settings$shifts[[1]]
}

# The likelihood structure a fit was made with (fits made before 0.2.0 are dense).
fit_structure <- function(fit) {
  fit$settings$structure %||% "dense"
}
