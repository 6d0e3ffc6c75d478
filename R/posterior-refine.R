#' Refine the emulator where the posterior lies, until it can be trusted
#'
#' The closed loop of a calibration in one call: [validate_emulator()] checks
#' the emulator against the simulator at the posterior; while it cannot be
#' trusted, [design_posterior()] lays `n` runs over the posterior's
#' intervals, the simulator runs them ([simulate_design()]), and the fit is
#' redone on all the runs with its own settings (priors, sampler, seed,
#' discrepancy terms). It stops when the emulator can be trusted or after
#' `rounds` refinements, and then says, with a warning of class
#' `bayesbem_warning_emulator`, that the last verdict still did not trust it.
#'
#' Why: with many field rows the posterior is narrower than a small design's
#' emulator error, which then sets where the intervals lie while every
#' sampler check passes (`bench/results/emulator-error.md`). Runs over the
#' posterior's
#' region make the emulator right where the calibration reads it; each round
#' may move the posterior, hence the loop.
#'
#' What it cannot mend: the runs go where the posterior is, so an emulator
#' wrong where the truth lies is not corrected there: a posterior held
#' along a ridge of parameters that trade off can stay there, and the check
#' then trusts the emulator. Where parameters trade off
#' (see [identifiability()]), add runs over the whole ridge as well, e.g.
#' with [design_lhs()] over the prior ranges.
#'
#' The added runs keep the simulation periods of the fit's runs (matched by
#' the observable inputs' values): a simulator over more periods serves, one
#' that lacks some of them is an error (class `bayesbem_error_simulator`).
#'
#' On a fit on several outputs the simulator gives every output: each
#' round's runs serve them all, and the emulator is trusted when every
#' output's is (`max_shift` the largest, `coverage` the lowest of the
#' outputs').
#'
#' @param fit A `bayesbem_fit` from [calibrate()].
#' @param simulator The `bayesbem_simulator` whose runs the fit was
#'   calibrated on.
#' @param n Number of runs added per round.
#' @param rounds Largest number of refinements.
#' @param ndraws,level,cache_dir Passed to [validate_emulator()]
#'   (`cache_dir` to [simulate_design()] too).
#' @param seed Seed of the first round's design; round `r` uses `seed + r -
#'   1`. `NULL`: random.
#' @param ... Unused.
#' @return The last fit (a `bayesbem_fit`, calibrated on the fit's runs and every
#'   added run, `fit$data$sim`), with `refinement`: one row per check
#'   (`round`, 0 for the fit given; `runs`, the runs it was calibrated on;
#'   `trusted`; `max_shift`, the largest absolute calibration shift in
#'   posterior sds; `coverage`, the share of the simulator's outputs inside
#'   the emulator's intervals) and `checks`, the [validate_emulator()]
#'   results.
#' @family design
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' top <- sim$parameters[sim$parameters$parameter %in%
#'                         c("equipment_power_density", "fan_total_efficiency",
#'                           "infiltration_per_exterior_area"), ]
#' # ten runs for three parameters: too few where the posterior lies
#' runs <- simulate_design(sim, design_lhs(top, n = 10, seed = 2))
#' field <- data.frame(y = seb_field$y, sim$x)
#' fit <- calibrate(field, runs, chains = 2, iter = 2000, seed = 7, refresh = 0)
#' fit <- refine_emulator(fit, sim, n = 6, rounds = 2, ndraws = 10, seed = 1)
#' fit$refinement
#' }
refine_emulator <- function(fit, simulator, n = 10, rounds = 3, ndraws = 40, level = 0.9,
                            seed = NULL, cache_dir = NULL, ...) {
  rlang::check_dots_empty()
  check_fit(fit)
  check_run_count(n)
  check_count(rounds)
  if (!is.null(seed)) check_count(seed)
  check <- function(fit) check_outcome(validate_emulator(fit, simulator, ndraws, level, cache_dir))
  checks <- list(check(fit))
  run_counts <- run_count(fit$data)
  done <- 0L
  while (!checks[[length(checks)]]$trusted && done < rounds) {
    done <- done + 1L
    design <- design_posterior(fit, n, level, seed = if (!is.null(seed)) seed + done - 1L)
    added <- simulate_design(simulator, design, cache_dir = cache_dir)
    data <- refined_data(fit, added)
    cli::cli_inform(c(i = "Round {done}: {nrow(design)} run{?s} where the posterior lies; calibrating again on {run_count(data)} runs."),
                    class = "bayesbem_message_refine")
    fit <- refit(fit, field = data)
    checks[[length(checks) + 1L]] <- check(fit)
    run_counts <- c(run_counts, run_count(data))
  }
  last <- checks[[length(checks)]]
  if (!last$trusted) {
    warn_bayesbem(c("After {done} round{?s} of refinement the emulator still cannot be trusted for the posterior.",
                    i = last$verdict,
                    i = "Refine again, e.g. {.code refine_emulator(fit, simulator, rounds = 2)}, or add runs over a wider region with {.fn design_lhs}."),
                  "emulator")
  }
  fit$refinement <- refinement_table(checks, run_counts)
  fit$checks <- lapply(checks, `[[`, "check")
  fit
}

# A validate_emulator() result, of one output or several (trusted when
# every output's emulator is: the largest shift, the lowest coverage).
check_outcome <- function(check) {
  each <- if (inherits(check, "bayesbem_emulator_checks")) check else list(check)
  verdicts <- vapply(each, `[[`, character(1), "verdict")
  if (length(each) > 1L) verdicts <- paste0(names(each), ": ", verdicts)
  list(check = check, trusted = all(vapply(each, `[[`, logical(1), "trusted")),
       verdict = paste(verdicts, collapse = " "),
       max_shift = max(vapply(each, function(ch) max(abs(ch$shift$shift)), numeric(1))),
       coverage = min(vapply(each, `[[`, numeric(1), "coverage")))
}

# The fit's data with the added runs (simulate_design()'s, of every
# output on several) at the fit's simulation periods, each parameter on the
# fit's scale.
refined_data <- function(fit, added, call = rlang::caller_env()) {
  data <- fit$data
  # the output column of a fit on several outputs (none on one)
  if (is.null(data$output)) {
    field <- field_table(data)
    runs <- rbind(data$sim, refinement_runs(data, added, call))
  } else {
    outputs <- names(data$outputs)
    if (!"output" %in% names(added) || !all(outputs %in% added$output)) {
      abort_bayesbem(c("The simulator's runs lack some of the fit's outputs, {.val {outputs}}.",
                       i = "Use the simulator whose runs the fit was calibrated on: one that gives every output."),
                     "simulator", call = call)
    }
    field <- outputs_long_table(data)
    runs <- outputs_long_table(data, function(one, k) {
      own <- added[added$output == k, setdiff(names(added), "output"), drop = FALSE]
      rbind(one$sim, refinement_runs(one, own, call))
    })
  }
  names <- output_data(data)[[1]]$names
  koh_data(field, runs, y = names$y, eta = names$eta, t = names$t, period = names$period,
           scales = t_scales(data$scaling), output = data$output)
}

# The added runs in the columns of the fit's runs, at the fit's simulation
# periods only (observable inputs matched to 6 significant digits).
refinement_runs <- function(data, added, call = rlang::caller_env()) {
  missing <- setdiff(names(data$sim), names(added))
  if (length(missing) > 0L) {
    abort_bayesbem(c("The simulator's runs lack column{?s} {.field {missing}} of the fit's runs.",
                     i = "Use the simulator whose runs the fit was calibrated on."),
                   "simulator", call = call)
  }
  key <- function(x) value_keys(x[data$names$x_sim])
  periods <- unique(key(data$sim))
  lacking <- setdiff(periods, key(added))
  if (length(lacking) > 0L) {
    abort_bayesbem(c("The simulator's periods lack {length(lacking)} of the {length(periods)} simulation period{?s} of the fit's runs.",
                     i = "The added runs must be at the periods of the fit's runs ({.field {data$names$x_sim}} matched by value): use the simulator whose runs the fit was calibrated on."),
                   "simulator", call = call)
  }
  added[key(added) %in% periods, names(data$sim), drop = FALSE]
}

# The number of simulation runs (distinct parameter settings) of a
# bayesbem_data, or of each output of a bayesbem_outputs (they share them).
run_count <- function(data) nrow(unique(output_data(data)[[1]]$tc))

# One row per check of refine_emulator().
refinement_table <- function(checks, run_counts) {
  data.frame(
    round = seq_along(checks) - 1L,
    runs = run_counts,
    trusted = vapply(checks, `[[`, logical(1), "trusted"),
    max_shift = vapply(checks, `[[`, numeric(1), "max_shift"),
    coverage = vapply(checks, `[[`, numeric(1), "coverage")
  )
}
