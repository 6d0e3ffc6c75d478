# The draws predictions are made of: the fit's parameters per posterior
# draw, y, eta and delta at new inputs jointly per draw (on the
# conditionals of R/gp-conditioning.R), the field given the runs at a
# draw, the inputs they are made at and the measured outputs they are
# compared with.

# Draws (rows) by points (columns) of y, eta and delta in physical units,
# sampled jointly per posterior draw so that y = eta + delta (+ noise); and
# the tf draws (rows, [0, 1] scale) they were conditioned on. `types`: which
# of y and eta are needed besides delta (an additive fit's eta is known
# only at the field rows; NA when not needed).
predict_draws <- function(fit, newdata, ndraws = NULL, noise = FALSE, types = c("y", "eta")) {
  data <- fit$data
  pars <- draw_parameters(fit, ndraws)
  joint <- if (is_additive(fit)) additive_joint(fit, newdata, pars, types) else
    gp_joint(fit, newdata, pars)
  eta <- joint$eta
  delta <- joint$delta
  if (length(data$covariates) > 0L) {
    gamma <- do.call(rbind, lapply(pars, `[[`, "gamma"))
    delta <- delta + gamma %*% t(scale_covariates(data, newdata))
  }
  y <- eta + delta
  if (noise) {
    y <- y + noise_matrix(pars, noise_weights(data, newdata), noise_rows(fit, newdata),
                          months = noise_months(fit, newdata), known = joint$shift)
  }
  s <- data$scaling
  list(y = unscale_y(y, s), eta = unscale_y(eta, s), delta = unscale_y_spread(delta, s),
       tf = do.call(rbind, lapply(pars, `[[`, "tf")))
}

# The AR(1) segments of the rows of `x` for a fit with AR(1) noise (NULL
# for white noise), and their months for a fit with a shift per month
# (NULL without): from `times`, else x's period column, else the field
# rows' when x is the field rows in order.
noise_rows <- function(fit, x, times = NULL, call = rlang::caller_env()) {
  if (is_ar1(fit$settings)) rows_layout(fit, x, times, noise_segments, fit_segments, call)
}

noise_months <- function(fit, x, times = NULL, call = rlang::caller_env()) {
  if (has_shifts(fit$settings)) rows_layout(fit, x, times, period_months, fit_shifts, call)
}

# `from_times` of the rows' times (`times`, else x's period column), or the
# fit's own `of_fit` when x is its field rows in order.
rows_layout <- function(fit, x, times, from_times, of_fit, call) {
  data <- fit$data
  period <- data$names$period
  times <- times %||% if (!is.null(period)) x[[period]]
  if (!is.null(times)) {
    return(from_times(times))
  }
  same <- nrow(x) == data$n && all(value_keys(x[data$names$x]) == value_keys(data$field[data$names$x]))
  if (!same) {
    abort_bayesbem(c("Noise of a fit with AR(1) noise or a shift per month needs the times of the rows.",
                     i = "Give {.arg newdata} the column {.field {period %||% \"time\"}}, or leave out the noise."),
                   "columns", call = call)
  }
  of_fit(fit)
}

# Draws (rows) by new rows (columns) of eta and delta, scaled, from the
# Gaussian processes' joint conditional (koh_conditional()) per draw.
gp_joint <- function(fit, newdata, pars) {
  g <- gp_geometry(fit$data, scale_newdata(fit$data, newdata), fit_structure(fit))
  n_new <- nrow(newdata)
  joint <- vapply(pars, function(par) {
    cond <- koh_conditional(g, par)
    rmvnorm_psd(cond$mean, cond$cov)
  }, numeric(2 * n_new))
  joint <- matrix(joint, nrow = 2 * n_new)
  list(eta = t(joint[seq_len(n_new), , drop = FALSE]),
       delta = t(joint[n_new + seq_len(n_new), , drop = FALSE]))
}

sampled_predictions <- function(fit, newdata, type, call = rlang::caller_env()) {
  if (is.null(fit$predict_at)) {
    abort_bayesbem(c("This fit has no predictions sampled in Stan.",
                     i = "Calibrate with {.code predict_at = <data frame of inputs>}, or use {.code method = \"conditional\"}."),
                   "argument", call = call)
  }
  if (!is.null(newdata) || type != "y") {
    abort_bayesbem(c("{.code method = \"sampled\"} gives {.code type = \"y\"} at the fit's {.arg predict_at} inputs only.",
                     i = "Leave {.arg newdata} empty, or use {.code method = \"conditional\"}."),
                   "argument", call = call)
  }
  unscale_y(stan_draws(fit, "y_pred"), fit$data$scaling)
}

# The field rows' observable inputs, and the covariates of any discrepancy terms.
field_inputs <- function(data) {
  x <- data$field[data$names$x]
  extra <- data$covariates[setdiff(names(data$covariates), names(x))]
  if (length(extra) > 0L) cbind(x, extra) else x
}

# The covariates of a fit's discrepancy terms at `newdata`, scaled as in the fit.
scale_covariates <- function(data, newdata, call = rlang::caller_env()) {
  needed <- names(data$covariates)
  # region terms added by extend() are rebuilt from their names
  for (name in setdiff(needed, names(newdata))) {
    values <- region_values(name, newdata)
    if (!is.null(values)) newdata[[name]] <- values
  }
  missing <- setdiff(needed, names(newdata))
  if (length(missing) > 0L) {
    abort_bayesbem(c("{.arg newdata} has no column{?s} {.field {missing}}.",
                     i = "This fit has discrepancy terms in {.field {needed}}: give their values or the columns they are made of (to {.fn predict_scenario}, {.fn savings} and {.fn avoided_energy}: in {.arg covariates})."),
                   "columns", call = call)
  }
  check_numeric_complete(newdata, needed, "newdata", call = call)
  sweep(as.matrix(newdata[needed]), 2, data$h_scale, "/")
}

# Inputs and measured outputs to compare predictions with: the field data by
# default, otherwise `newdata` with `obs` (NA when not given).
prediction_set <- function(fit, newdata, obs, call = rlang::caller_env()) {
  if (is.null(newdata)) {
    return(list(x = field_inputs(fit$data), obs = fit$data$field[[fit$data$names$y]]))
  }
  if (!is.null(obs) && (!is.numeric(obs) || length(obs) != NROW(newdata))) {
    abort_bayesbem(c("{.arg obs} must be numeric with one value per row of {.arg newdata}.",
                     x = "It has {length(obs)} value{?s} for {NROW(newdata)} row{?s}."),
                   "argument", call = call)
  }
  list(x = newdata, obs = obs %||% rep(NA_real_, NROW(newdata)))
}

# The training set, and a held-out set when both `newdata` and `obs` are given.
evaluation_sets <- function(fit, newdata, obs, call = rlang::caller_env()) {
  if (xor(is.null(newdata), is.null(obs))) {
    abort_bayesbem("Give both {.arg newdata} and {.arg obs} for held-out data, or neither.",
                   "argument", call = call)
  }
  sets <- list(training = prediction_set(fit, NULL, NULL))
  if (!is.null(newdata)) sets[["held-out"]] <- prediction_set(fit, newdata, obs, call = call)
  sets
}

# Posterior draws of the model's parameters on the Stan scale, one list per draw
# (evenly spaced ones with `ndraws`; their indices in `attr(, "index")`).
draw_parameters <- function(fit, ndraws = NULL) {
  get <- function(par) stan_draws(fit, par)
  tf <- get("tf")
  beta_eta <- get("beta_eta")
  beta_delta <- get("beta_delta")
  lambda <- cbind(get("lambda_eta"), get("lambda_delta"), get("lambda_e"))
  gamma <- if (length(fit$data$covariates) > 0L) get("gamma") else matrix(0, nrow(tf), 0)
  select <- mean_selection(fit$priors, fit$data$p, fit$data$q)
  coef <- if (ncol(select) > 0L) get("b") %*% t(select) else matrix(0, nrow(tf), nrow(select))
  idx <- draw_subset(nrow(tf), ndraws)
  additive <- is_additive(fit)
  phi <- if (is_ar1(fit$settings)) get("phi") else matrix(0, nrow(tf))
  lambda_shift <- if (has_shifts(fit$settings)) get("lambda_shift") else matrix(Inf, nrow(tf))
  draws <- lapply(idx, function(i) {
    list(tf = tf[i, ], beta_eta = beta_eta[i, ], beta_delta = beta_delta[i, ],
         lambda_eta = lambda[i, 1], lambda_delta = lambda[i, 2], lambda_e = lambda[i, 3],
         gamma = gamma[i, ], coef = coef[i, ], nugget = fit$priors$nugget, additive = additive,
         phi = phi[i, 1], lambda_shift = lambda_shift[i, 1])
  })
  structure(draws, index = idx)
}

# Evenly spaced draws, so that results do not depend on the random seed.
draw_subset <- function(total, ndraws) {
  if (is.null(ndraws) || ndraws >= total) {
    return(seq_len(total))
  }
  check_count(ndraws)
  unique(round(seq(1, total, length.out = ndraws)))
}

# The field outputs given the simulation runs alone, at the draw's tf:
# field_given_runs() with the emulator mean h(x, tf)' b added back, so that
# `mean` is the emulator's mean at the field rows; under the emulator stage
# 2 calibrated with (basis_field() for a basis fit).
runs_field <- function(g, par) {
  if (!is.null(g$basis)) {
    return(basis_field(g, par))
  }
  fm <- field_given_runs(residual_geometry(g, par), par)
  fm$mean <- fm$mean + emulator_mean(g$xf, par$tf, par$coef)
  fm
}

# The emulator's mean at the field rows given the simulation runs alone, at
# the parameters `tf` (scaled).
runs_mean <- function(g, par, tf) {
  par$tf <- tf
  runs_field(g, par)$mean
}

# The simulator's sensitivity to each parameter at the field rows, d eta /
# d tf (field rows by parameters): central differences of runs_mean(), step
# h on the scaled scale, kept inside [0, 1].
runs_sensitivity <- function(g, par, h = 0.01) {
  vapply(seq_along(par$tf), function(k) {
    up <- par$tf
    down <- par$tf
    up[k] <- min(up[k] + h, 1)
    down[k] <- max(down[k] - h, 0)
    (runs_mean(g, par, up) - runs_mean(g, par, down)) / (up[k] - down[k])
  }, numeric(g$n))
}
