# The simulator at posterior draws: runs for scenarios, savings and the
# emulator's check (each draw's calibration parameters with a scenario's
# changes), and the discrepancy given the simulator's output there.

# Every run failed: say why, with the simulator's own messages (the
# distinct ones, first few), not only that they failed.
abort_all_failed <- function(failed, call) {
  reasons <- utils::head(unique(failed$error), 3)
  reasons <- gsub("}", "}}", gsub("{", "{{", reasons, fixed = TRUE), fixed = TRUE)
  abort_bayesbem(c("Every simulation run at the posterior draws failed.",
                   stats::setNames(reasons, rep("x", length(reasons))),
                   i = "Run the simulator at one draw with {.fn simulate_design} to see the whole message."),
                 "simulation", call = call)
}

# A simulator whose runs are made once for every output asked of it in
# this session (output_simulator() of it, one per output): its function
# keeps each run's outputs by parameter values. Its cache key stays the
# simulator's own.
shared_runs <- function(simulator) {
  made <- new.env(parent = emptyenv())
  fun <- simulator$fun
  key <- simulator_key(simulator)
  simulator$fun <- function(params, x) {
    id <- rlang::hash(list(params, x))
    if (is.null(made[[id]])) made[[id]] <- fun(params, x)
    made[[id]]
  }
  simulator$key <- key
  simulator
}

# `tool(k, fit, ...)` on each output `k` of a fit on several outputs, by
# output: its name, its view, then each of `scenarios` (simulators or scenarios of
# one simulator that gives every output) cut to that output. A simulator
# runs once per draw for every output (shared_runs()).
each_output_runs <- function(fit, scenarios, tool, call = rlang::caller_env()) {
  shared <- lapply(scenarios, function(s) {
    if (inherits(s, "bayesbem_scenario")) {
      s$simulator <- shared_runs(s$simulator)
      return(s)
    }
    check_simulator(s, arg = "simulator", call = call)
    shared_runs(s)
  })
  cut <- function(s, k) {
    if (!inherits(s, "bayesbem_scenario")) {
      return(output_simulator(s, k))
    }
    s$simulator <- output_simulator(s$simulator, k)
    s
  }
  outputs <- names(fit$outputs)
  lapply(stats::setNames(outputs, outputs), function(k) {
    do.call(tool, c(list(k, fit$outputs[[k]]), lapply(shared, cut, k = k)))
  })
}

# The scenarios' simulators run at the same posterior draws (paired): a
# draw is kept only where every scenario's run succeeded. Returns the draws
# (Stan scale), their indices and each scenario's outputs (draws by periods).
scenario_runs <- function(fit, scenarios, ndraws, cache_dir, call = rlang::caller_env()) {
  check_count(ndraws, call = call)
  draws <- draw_parameters(fit, ndraws)
  outputs <- lapply(scenarios, function(s) {
    check_fit_simulator(fit, s$simulator, call)
    design <- scenario_design(s, draw_design(fit, s$simulator, draws), call)
    run_at_draws(s$simulator, design, cache_dir, call)
  })
  ok <- Reduce(`&`, lapply(outputs, function(m) stats::complete.cases(m)))
  list(draws = draws[ok], index = attr(draws, "index")[ok],
       simulated = lapply(outputs, function(m) m[ok, , drop = FALSE]))
}

# The calibration parameters of each draw in physical units, one row per
# draw, within the simulator's ranges (unscaling can pass a bound by
# rounding).
draw_design <- function(fit, simulator, draws) {
  data <- fit$data
  tf <- unscale_t(do.call(rbind, lapply(draws, `[[`, "tf")), data$scaling)
  range <- simulator$parameters[match(data$names$t, simulator$parameters$parameter), ]
  design <- as.data.frame(tf)
  names(design) <- data$names$t
  design[] <- lapply(seq_along(design), function(k) {
    pmin(pmax(design[[k]], range$min[k]), range$max[k])
  })
  design
}

# A scenario's changes applied to the draws' design: scaled parameters are
# multiplied (an uncalibrated one from its initial value), set ones replaced.
scenario_design <- function(scenario, design, call) {
  table <- scenario$simulator$parameters
  for (name in names(scenario$scale)) {
    base <- design[[name]] %||% rep(table$initial[table$parameter == name], nrow(design))
    design[[name]] <- base * scenario$scale[[name]]
  }
  for (name in names(scenario$set)) design[[name]] <- rep(scenario$set[[name]], nrow(design))
  check_scenario_range(scenario$simulator, design[c(names(scenario$scale), names(scenario$set))],
                       "change", call = call)
  design
}

# The simulator's outputs at each row of `design` (rows; NA rows for failed
# runs); when every run fails, an error with the simulator's reasons.
run_at_draws <- function(simulator, design, cache_dir, call) {
  out <- simulate_design(simulator, design, cache_dir = cache_dir)
  eta <- matrix(NA_real_, nrow(design), nrow(simulator$x))
  ok <- setdiff(seq_len(nrow(design)), attr(out, "failed")$run)
  if (length(ok) == 0L) abort_all_failed(attr(out, "failed"), call)
  eta[ok, ] <- matrix(out$eta, nrow = length(ok), byrow = TRUE)
  eta
}

# The simulator must take the fit's calibration parameters and report its
# observable inputs.
check_fit_simulator <- function(fit, simulator, call) {
  check_simulator(simulator, call = call)
  data <- fit$data
  unknown <- setdiff(data$names$t, simulator$parameters$parameter)
  missing_x <- setdiff(data$names$x, names(simulator$x))
  if (length(unknown) > 0L || length(missing_x) > 0L) {
    abort_bayesbem(c("{.arg simulator} does not match the fit.",
                     x = if (length(unknown) > 0L) "It has no parameter{?s} {.field {unknown}}.",
                     x = if (length(missing_x) > 0L) "It has no observable input{?s} {.field {missing_x}}.",
                     i = "Use the simulator whose runs the fit was calibrated on."),
                   "simulator", call = call)
  }
}

# The discrepancy at the scenario's inputs, one draw per row of `simulated`
# (physical units): for each posterior draw, delta given the data and
# eta = the simulator's output there (delta_given_eta()), plus the
# parametric terms of extend(); and (`shift`, additive fits with a shift
# per month) the training months' shifts drawn with it, standardised.
scenario_delta <- function(fit, inputs, simulated, draws) {
  data <- fit$data
  x <- withCallingHandlers(
    scale_newdata(data, inputs, arg = "scenario"),
    bayesbem_warning_extrapolation = function(w) {
      warn_bayesbem(c("The scenario's weather lies outside the weather the model was calibrated on.",
                      i = "The simulator runs there; the discrepancy extrapolates, towards its mean."),
                    "extrapolation")
      invokeRestart("muffleWarning")
    })
  joint <- if (is_additive(fit)) {
    additive_joint(fit, inputs, draws, types = "delta", x_new = x)
  } else {
    list(delta = gp_delta_given_eta(fit, x, scale_y(simulated, data$scaling), draws))
  }
  delta <- joint$delta
  if (length(data$covariates) > 0L) {
    gamma <- do.call(rbind, lapply(draws, `[[`, "gamma"))
    delta <- delta + gamma %*% t(scale_covariates(data, inputs))
  }
  list(delta = unscale_y_spread(delta, data$scaling), shift = joint$shift)
}

# delta at scaled inputs x given the simulator's outputs s there (draws by
# rows), one draw each from delta_given_eta().
gp_delta_given_eta <- function(fit, x, s, draws) {
  g <- gp_geometry(fit$data, x, fit_structure(fit))
  delta <- vapply(seq_along(draws), function(i) {
    delta_given_eta(koh_conditional(g, draws[[i]]), s[i, ])
  }, numeric(ncol(s)))
  t(matrix(delta, ncol = length(draws)))
}

# One draw of delta from the joint Gaussian (eta, delta) of
# koh_conditional() given eta = s: mean m_d + C_de C_ee^-1 (s - m_e),
# covariance C_dd - C_de C_ee^-1 C_ed. The gain C_de C_ee^-1 stays bounded
# where the runs pin eta down (it tends to -P_dd^-1 P_de of the precision),
# so a floor of 1e-10 of the largest variance on C_ee's diagonal only
# guards rounding.
delta_given_eta <- function(cond, s) {
  n <- length(s)
  e <- seq_len(n)
  d <- n + e
  c_ee <- cond$cov[e, e, drop = FALSE]
  diag(c_ee) <- diag(c_ee) + 1e-10 * max(diag(c_ee), .Machine$double.xmin)
  r <- jittered_chol(c_ee)
  k <- backsolve(r, t(cond$cov[d, e, drop = FALSE]), transpose = TRUE)
  w <- backsolve(r, s - cond$mean[e], transpose = TRUE)
  rmvnorm_psd(cond$mean[d] + drop(crossprod(k, w)),
              cond$cov[d, d, drop = FALSE] - crossprod(k))
}

# Observation noise N(0, w_i / lambda_e) of each draw (rows) at each period
# of a table of inputs (columns), physical units; AR(1) over the periods'
# `times` for a fit with AR(1) noise; with a shift per month, the months'
# shifts (the training months' from `known`, additive_joint()'s `shift`).
noise_draws <- function(fit, draws, x, times = NULL, known = NULL) {
  fit$data$scaling$y_scale *
    noise_matrix(draws, noise_weights(fit$data, x), noise_rows(fit, x, times),
                 months = noise_months(fit, x, times), known = known)
}
