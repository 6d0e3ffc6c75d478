#' Check the emulator against the simulator at the posterior
#'
#' The closed loop of a calibration: `validate_emulator()` reruns the
#' simulator (EnergyPlus, the embedded model or any [simulator()]) at
#' `ndraws` posterior draws of the calibration parameters and compares its
#' real outputs with the emulator's predictions at those draws. For each
#' draw the emulator's prediction is the Gaussian conditional of
#' `eta(x, tf)` given all data under that draw's hyperparameters (as in
#' [predict.bayesbem_fit()] with `type = "eta"`); for a fit calibrated with the
#' basis emulator (`calibrate(emulator = "basis")`, the default above 36
#' field rows) it is that emulator's given the runs, the error stage 2
#' calibrated with. Its `level` interval should hold the simulator's output
#' at about that rate.
#'
#' The calibration shift reads the emulator's error through the
#' calibration: for each draw, were the field outputs the simulator's
#' outputs `s` at the draw's `tf`, their likelihood given the runs (under
#' the draw's hyperparameters: the emulator's uncertainty `S_e`, the
#' discrepancy and the noise, covariance `S`, mean `m(t)`; a basis fit's
#' own) would peak at `tf + Delta`, `Delta = A J' S^-1 (s - m(tf))`,
#' `A = (J' S^-1 J)^-1` (one Gauss-Newton step; `J = dm/dt` by central
#' differences). `shift` is the median of `Delta` over the draws in
#' posterior sds of each parameter; `z` the median of `Delta` over its sd
#' were the emulator's error as it states it, `s - m(tf) ~ N(0, S_e)`:
#' `Delta ~ N(0, A J' S^-1 S_e S^-1 J A)`. An error small at every period
#' can still move the calibration when it is alike over many periods (a
#' year of daily data: `bench/results/emulator-error.md`). An honest
#' emulator's error moves the calibration too, by about its share of the
#' posterior's spread, which the posterior already holds: the shift alone
#' says nothing wrong, the shift beyond the stated error does. The check
#' reads the emulator where the posterior lies: an emulator that is right
#' there but wrong where the truth lies can hold the posterior near a run
#' it reproduces well, and passes.
#'
#' The verdict: the emulator can be trusted for this posterior when at least
#' `level - 0.1` of the simulator's outputs lie in the emulator's intervals,
#' its error (root mean square) is below the observation noise's standard
#' deviation, and it moves no calibration parameter both by more than half
#' a posterior sd (a 90 % interval displaced by half its sd still holds the
#' truth 86 % of the time; by one sd, 74 %) and by more than its stated
#' error explains (`|z|` above `qnorm(1 - 0.05 / q)` for `q` parameters, so
#' that an honest emulator fails this part in at most 10 % of fits).
#' Otherwise the report says why,
#' naming the parameters it moves, and from the distance of
#' the draws to the nearest simulation run relative to the runs' distances
#' to each other: posterior draws farther from the runs than the runs are
#' from each other mean the design missed the posterior's region (add runs
#' there); otherwise the runs are too few for the emulator (add runs).
#' Either way [design_posterior()] lays new runs over the posterior's
#' intervals; bind their outputs to the runs and calibrate again.
#'
#' `posterior_simulate()` returns the real simulator's outputs at the
#' posterior draws: the calibrated model's predictions without the emulator
#' (and without the discrepancy).
#'
#' Both run the simulator through [simulate_design()]: the `future` plan
#' decides where, `cache_dir` caches the runs, and failed runs are left out
#' with a warning. The simulator's observable inputs must contain the fit's
#' field inputs (matched by value, so a simulator over more periods than the
#' fit's training data serves); a simulator with as many periods as the fit
#' but other input values is taken in order, with a warning of class
#' `bayesbem_warning_simulator`.
#'
#' On a fit on several outputs, with the simulator of them all,
#' `validate_emulator()` checks each output's emulator against that
#' output of the same runs (one run per draw serves every output) and
#' returns the checks in a list by output; `posterior_simulate()` stacks
#' the outputs' summaries with a first column `output` (or returns the
#' matrices in a list by output).
#'
#' @param fit A `bayesbem_fit`.
#' @param simulator A `bayesbem_simulator` whose parameters include the
#'   fit's calibration parameters (others are held at their initial values);
#'   on several outputs, one that gives them all.
#' @template args-ndraws-runs
#' @param level Probability of the emulator's intervals (`validate_emulator()`),
#'   or of the central interval `posterior_simulate()` reports.
#' @template args-cache-dir
#' @param summary For `posterior_simulate()`: a data frame of summaries
#'   (`TRUE`) or a draws-by-periods matrix.
#' @param ... Unused.
#' @return `validate_emulator()`: an object of class `bayesbem_emulator_check`, a
#'   list with `table` (one row per draw and period: `draw`, `period`, the
#'   inputs, `simulated`, the emulator's `mean`, `sd`, `lower` and `upper`,
#'   and `inside`), `periods` (per period: mean error, RMSE and coverage),
#'   `coverage`, `rmse`, `noise_sd`, `shift` (per calibration parameter,
#'   `parameter`, `shift` and `z`, the draws' shifts in `attr(, "draws")`),
#'   `distance` (median distance of the
#'   draws to the nearest run over the runs' median nearest-neighbour
#'   distance), `trusted` and `verdict`; on several outputs, a
#'   `bayesbem_emulator_checks`, the list of them by output.
#'   `posterior_simulate()`: the
#'   field inputs with `mean`, `sd`, median and the central `level`
#'   interval's bounds (order statistics, as `predict()`'s) of the
#'   simulator's output, or the matrix.
#' @family diagnostics
#' @export
#' @examples
#' \donttest{
#' # seb_fit's runs came from EnergyPlus; the embedded model is another
#' # simulator, which the check exposes
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' check <- validate_emulator(seb_fit, sim, ndraws = 5)
#' check
#' posterior_simulate(seb_fit, sim, ndraws = 20)
#' }
validate_emulator <- function(fit, simulator, ndraws = 40, level = 0.9, cache_dir = NULL, ...) {
  rlang::check_dots_empty()
  check_probability(level)
  check_fit(fit)
  UseMethod("validate_emulator")
}

# Each output's check, from one run of the simulator per draw.
#' @export
validate_emulator.bayesbem_fit_outputs <- function(fit, simulator, ndraws = 40, level = 0.9,
                                                   cache_dir = NULL, ...) {
  checks <- each_output_runs(fit, list(simulator), function(k, fit, simulator) {
    validate_emulator(fit, simulator, ndraws = ndraws, level = level, cache_dir = cache_dir)
  })
  structure(checks, class = "bayesbem_emulator_checks")
}

#' @export
validate_emulator.bayesbem_fit <- function(fit, simulator, ndraws = 40, level = 0.9,
                                           cache_dir = NULL, ...) {
  runs <- posterior_runs(fit, simulator, ndraws, cache_dir)
  data <- fit$data
  x <- field_inputs(data)[data$names$x]
  g <- gp_geometry(data, scale_newdata(data, x), fit_structure(fit), fit$emulator$basis)
  n <- nrow(x)
  z <- stats::qnorm(1 - (1 - level) / 2)
  rows <- lapply(seq_along(runs$draws), function(i) {
    pred <- emulator_prediction(g, runs$draws[[i]])
    mean <- unscale_y(pred$mean, data$scaling)
    sd <- unscale_y_spread(sqrt(pred$var), data$scaling)
    data.frame(draw = runs$index[i], period = seq_len(n), x, simulated = runs$eta[i, ],
               mean = mean, sd = sd, lower = mean - z * sd, upper = mean + z * sd,
               row.names = NULL)
  })
  table <- do.call(rbind, rows)
  table <- table[!is.na(table$simulated), ]
  table$inside <- table$simulated >= table$lower & table$simulated <= table$upper
  emulator_verdict(table, fit, runs, level, calibration_shift(fit, g, runs))
}

# The emulator's prediction of eta at the field rows for one draw (scaled):
# `mean` and `var`. A basis fit's is the basis emulator's given the runs,
# mu + B w(tf) and diag(B diag(v(tf)) B') + s2r, the error stage 2
# calibrated with; otherwise the Gaussian conditional given all data, as
# predict(type = "eta").
emulator_prediction <- function(g, par) {
  if (!is.null(g$basis)) {
    eta <- basis_eta(g$basis, par$tf)
    return(list(mean = eta$mean, var = drop(g$basis$B^2 %*% eta$var) + g$basis$s2r))
  }
  cond <- koh_conditional(g, par)
  rows <- seq_len(g$n)
  list(mean = cond$mean[rows], var = pmax(diag(cond$cov)[rows], 0))
}

# How far the emulator's error at each draw moves the calibration: the
# median over the draws of emulator_shift()'s step in posterior sds of each
# parameter (`shift`) and of the step over its sd were the emulator's
# stated error its true error (`z`; scale of the emulator). A table of
# `parameter`, `shift` and `z`, the draws' shifts in `attr(, "draws")`.
calibration_shift <- function(fit, g, runs) {
  s <- (runs$eta - fit$data$scaling$y_center) / fit$data$scaling$y_scale
  ok <- which(stats::complete.cases(s))
  steps <- lapply(ok, function(i) emulator_shift(g, runs$draws[[i]], s[i, ]))
  delta <- matrix(vapply(steps, `[[`, numeric(fit$data$q), "shift"), ncol = length(ok))
  stated <- matrix(vapply(steps, `[[`, numeric(fit$data$q), "sd"), ncol = length(ok))
  posterior_sd <- apply(stan_draws(fit, "tf"), 2, stats::sd)
  shifts <- t(delta / posterior_sd)
  z <- t(delta / pmax(stated, .Machine$double.eps))
  structure(data.frame(parameter = fit$data$names$t, shift = apply(shifts, 2, stats::median),
                       z = apply(z, 2, stats::median), row.names = NULL),
            draws = shifts)
}

# For one draw: where the calibration would move were the field outputs the
# simulator's outputs `s` at the draw's tf (scaled). Given the runs, the
# field outputs are N(m(t), S) under the draw's hyperparameters
# (runs_field(): the emulator's uncertainty S_e, the discrepancy and the
# noise); the likelihood of s peaks at tf + Delta, by one Gauss-Newton step
# Delta = A J' S^-1 (s - m(tf)), A = (J' S^-1 J)^-1, J = dm/dt
# (runs_sensitivity()). Delta is the emulator's error seen through the
# calibration. Were that error as the emulator states, s - m(tf) ~ N(0, S_e)
# and Delta ~ N(0, A J' S^-1 S_e S^-1 J A): `sd` is the square root of its
# diagonal. Returns `shift` (Delta) and `sd`.
emulator_shift <- function(g, par, s) {
  fm <- runs_field(g, par)
  r <- chol(fm$cov)
  wj <- backsolve(r, runs_sensitivity(g, par), transpose = TRUE)
  we <- backsolve(r, s - fm$mean, transpose = TRUE)
  a <- solve(crossprod(wj))
  u <- backsolve(r, wj) %*% a
  s_e <- fm$cov - delta_cov(g$ff, par) - noise_cov(g, par)
  list(shift = drop(a %*% crossprod(wj, we)), sd = sqrt(pmax(diag(crossprod(u, s_e %*% u)), 0)))
}

#' @rdname validate_emulator
#' @export
posterior_simulate <- function(fit, simulator, ndraws = 40, summary = TRUE,
                               level = 0.9, cache_dir = NULL, ...) {
  rlang::check_dots_empty()
  check_bool(summary)
  check_fit(fit)
  UseMethod("posterior_simulate")
}

# Each output's runs, by output (their summaries stacked).
#' @export
posterior_simulate.bayesbem_fit_outputs <- function(fit, simulator, ndraws = 40, summary = TRUE,
                                                    level = 0.9, cache_dir = NULL, ...) {
  each <- each_output_runs(fit, list(simulator), function(k, fit, simulator) {
    posterior_simulate(fit, simulator, ndraws = ndraws, summary = summary, level = level,
                       cache_dir = cache_dir)
  })
  if (summary) stack_outputs(each) else each
}

#' @export
posterior_simulate.bayesbem_fit <- function(fit, simulator, ndraws = 40, summary = TRUE,
                                            level = 0.9, cache_dir = NULL, ...) {
  runs <- posterior_runs(fit, simulator, ndraws, cache_dir)
  eta <- runs$eta[stats::complete.cases(runs$eta), , drop = FALSE]
  if (!summary) {
    return(eta)
  }
  summarise_columns(eta, field_inputs(fit$data)[fit$data$names$x], level)
}

# The simulator run at evenly spaced posterior draws: the draws (Stan
# scale), their indices, and the outputs at the fit's field rows (draws by
# rows; NA rows for failed runs).
posterior_runs <- function(fit, simulator, ndraws, cache_dir, call = rlang::caller_env()) {
  check_fit(fit, call = call)
  check_count(ndraws, call = call)
  rows <- simulator_rows(fit, simulator, call)
  draws <- draw_parameters(fit, ndraws)
  design <- draw_design(fit, simulator, draws)
  eta <- run_at_draws(simulator, design, cache_dir, call)
  list(draws = draws, index = attr(draws, "index"), eta = eta[, rows, drop = FALSE],
       design = design)
}

# The simulator's periods that are the fit's field rows, matched by the
# observable inputs' values; the calibration parameters must be the
# simulator's.
simulator_rows <- function(fit, simulator, call) {
  check_fit_simulator(fit, simulator, call)
  data <- fit$data
  field <- field_inputs(data)[data$names$x]
  rows <- match_in_order(value_keys(field), value_keys(simulator$x[data$names$x]))
  if (anyNA(rows) && nrow(simulator$x) == nrow(field)) {
    # as many periods as the fit: taken in order, the differences reported
    spread <- vapply(data$names$x, function(v) diff(range(field[[v]])), numeric(1))
    gap <- vapply(data$names$x, function(v) max(abs(simulator$x[[v]] - field[[v]])), numeric(1)) /
      pmax(spread, .Machine$double.eps)
    differ <- data$names$x[gap > 1e-6]
    warn_bayesbem(c("The simulator's observable inputs differ from the fit's field inputs in {.field {differ}} (at most {round(100 * max(gap), 1)}% of their range); its periods are taken in order.",
                    i = "The emulator is evaluated at the fit's inputs and the simulator at its own."),
                  "simulator")
    return(seq_len(nrow(field)))
  }
  if (anyNA(rows)) {
    abort_bayesbem(c("{sum(is.na(rows))} of the fit's {length(rows)} field period{?s} {?is/are} not among the simulator's periods.",
                     i = "The simulator's observable inputs must include each field row's values ({.field {data$names$x}})."),
                   "simulator", call = call)
  }
  rows
}

# Coverage, error, the calibration's shift and the verdict of
# validate_emulator(). A parameter is moved when its shift is both material
# and more than the emulator's stated error explains: beyond `max_shift`
# posterior sds (a 90 % interval displaced by 0.5 of its sd still holds the
# truth 86 % of the time, by 1 sd 74 %) and beyond `z_limit` sds of the
# shift an honest emulator would cause (calibration_shift()'s z, N(0, 1)
# per parameter for one draw; qnorm(1 - 0.05 / q) flags at most 10 % of fits
# with an honest emulator, and fewer where the draws' errors differ, as the
# median over draws is less spread). An honest emulator's error is part of
# the posterior's spread: its shift alone says nothing wrong.
emulator_verdict <- function(table, fit, runs, level, shift, max_shift = 0.5,
                             z_limit = stats::qnorm(1 - 0.05 / fit$data$q)) {
  data <- fit$data
  error <- table$simulated - table$mean
  noise_sd <- mean(vapply(runs$draws, function(p) 1 / sqrt(p$lambda_e), numeric(1))) *
    data$scaling$y_scale
  periods <- data.frame(
    period = sort(unique(table$period)),
    error = as.vector(tapply(error, table$period, mean)),
    rmse = as.vector(tapply(error^2, table$period, function(e) sqrt(mean(e)))),
    coverage = as.vector(tapply(table$inside, table$period, mean))
  )
  coverage <- mean(table$inside)
  rmse <- sqrt(mean(error^2))
  distance <- design_distance(data, runs$draws)
  outputs_ok <- coverage >= level - 0.1 && rmse <= noise_sd
  moved <- abs(shift$shift) > max_shift & abs(shift$z) > z_limit
  trusted <- outputs_ok && !any(moved)
  outputs <- sprintf("%.0f%% of the simulator's outputs lie in its %.0f%% intervals (RMSE %s, noise sd %s)",
                     100 * coverage, 100 * level, format(signif(rmse, 3)), format(signif(noise_sd, 3)))
  largest <- which.max(abs(shift$shift))
  verdict <- if (trusted) {
    sprintf("The emulator can be trusted for this posterior: %s, and its error moves no calibration parameter by more than %s posterior sd beyond what its stated error explains (largest shift: %s, %s sd, z %s).",
            outputs, max_shift, shift$parameter[largest], format(round(shift$shift[largest], 2)),
            format(round(shift$z[largest], 1)))
  } else {
    why <- if (distance > 1) {
      sprintf("the posterior lies away from the runs (%.1f times farther from the nearest run than the runs are from each other): add runs in the posterior's region, e.g. with design_posterior(fit, n = 10), and calibrate again.", distance)
    } else {
      "the runs are too few for the emulator where the posterior lies: add runs there, e.g. with design_posterior(fit, n = 10), and calibrate again."
    }
    found <- if (any(moved)) {
      sprintf("%s; its error moves %s posterior sd, more than its stated error explains, so %s intervals lie where the emulator, not the data, puts them",
              outputs, and_list(sprintf("%s by %s", shift$parameter[moved],
                                        format(round(shift$shift[moved], 2), trim = TRUE))),
              if (sum(moved) > 1L) "their" else "its")
    } else {
      outputs
    }
    sprintf("The emulator cannot be trusted for this posterior: %s; %s", found, why)
  }
  structure(list(table = table, periods = periods, coverage = coverage, rmse = rmse,
                 noise_sd = noise_sd, shift = shift, distance = distance, level = level,
                 trusted = trusted, verdict = verdict, y = data$names$y),
            class = "bayesbem_emulator_check")
}

# Median distance of the draws' tf to the nearest run, over the runs' median
# distance to their nearest neighbour (scaled parameters).
design_distance <- function(data, draws) {
  tc <- unique(as.matrix(data$tc))
  tf <- do.call(rbind, lapply(draws, `[[`, "tf"))
  nearest <- function(a, b, self) {
    d <- sqrt(pmax(outer(rowSums(a^2), rowSums(b^2), "+") - 2 * a %*% t(b), 0))
    if (self) diag(d) <- Inf
    apply(d, 1, min)
  }
  if (nrow(tc) < 2L) {
    return(Inf)
  }
  stats::median(nearest(tf, tc, FALSE)) / stats::median(nearest(tc, tc, TRUE))
}

#' @export
print.bayesbem_emulator_checks <- function(x, ...) {
  rlang::check_dots_empty()
  for (k in names(x)) {
    cat(sprintf("%s:\n", k))
    print(x[[k]])
    cat("\n")
  }
  invisible(x)
}

#' @export
print.bayesbem_emulator_check <- function(x, ...) {
  rlang::check_dots_empty()
  cat(strwrap(x$verdict), sep = "\n")
  cat("\nShift of the calibration by the emulator's error (posterior sd; z: over the shift its stated error explains):\n")
  print(data.frame(parameter = x$shift$parameter, shift = round(x$shift$shift, 2),
                   z = round(x$shift$z, 1)), row.names = FALSE)
  cat("\nPer period:\n")
  print_rounded(x$periods, 3)
  invisible(x)
}
