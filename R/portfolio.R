#' Calibrate a portfolio of buildings, one job each, resumable
#'
#' Runs each building's pipeline (its runs, [calibrate()], the convergence
#' check, Guideline 14's metrics at the calibration, the data's sufficiency,
#' the discrepancy's verdict and, with `retrofit`, the [savings()] of a
#' measure) as one job through `future`, so that the plan decides where the
#' jobs run: `future::plan(future::multisession, workers = 2)` on a laptop,
#' `future::plan(future.batchtools::batchtools_slurm)` (or `_sge`, `_lsf`,
#' `_openlava`, `_torque`) on a cluster. One progress bar counts the
#' buildings (`progressr`).
#'
#' Each building's result is written to `dir` as it finishes, one file per
#' building (`<id>.rds`, written under another name and renamed, so that a
#' file is whole or absent). A building that fails is recorded with its
#' error and never stops the others. A second call with the same `dir`
#' runs only the buildings with no result or a failed one, so a portfolio
#' stopped midway (a killed session, a cluster's time limit) resumes where
#' it stopped. Before any job is sent, each building with its runs given
#' passes the checks [calibrate()] makes before sampling (the size of its
#' fit against the memory and time limits, the runs' reach of the meter,
#' the arguments): one that cannot run is recorded as refused, with the
#' error, and not sent.
#'
#' A building's job is seeded by its `seed`, so a building gives the same
#' result under any plan. Its warnings (convergence, a posterior at a
#' range limit) are kept in its record, not printed: `summary()` shows
#' whether each converged and how many warnings it had.
#'
#' @param buildings A data frame, one row per building (or meter): `id`
#'   (unique names, used for the files), `field` (a list of field tables,
#'   one output each: a building's several meters are rows of their own),
#'   and either `runs` (a list of run tables) or `simulator` (a list of
#'   simulators) with `design` (a list of designs, e.g. [design_lhs()]),
#'   whose runs the job makes. With `retrofit`, `simulator` is needed.
#'   Optional: `seed` (a whole number per building; default the row's
#'   number plus `seed`).
#' @param dir The results directory (created if absent).
#' @param retrofit `NULL`, or a function of a building's simulator giving
#'   its retrofit [scenario()] (e.g. `function(sim) scenario(sim, scale =
#'   c(lighting_power_density = 0.5))`); its savings are against
#'   `scenario(simulator)`, over the simulator's periods.
#' @param ndraws Posterior draws at which the simulator runs for the
#'   savings.
#' @param seed The seed of the first building when `buildings` has no
#'   `seed` column.
#' @param keep_fits Also store each fit in its building's file (large).
#' @param ... Arguments to [calibrate()] (e.g. `chains`, `cores`: on
#'   several workers, `cores = 1` keeps one core per worker).
#' @return A `bayesbem_portfolio`: the results directory and each
#'   building's record (`status`: `"done"`, `"failed"` or `"refused"`, with
#'   `error` and `error_class`, or the results). [summary()] gives the
#'   table by building and the portfolio's total savings;
#'   [plot_portfolio()] plots them.
#' @family portfolio
#' @export
#' @examples
#' \donttest{
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' pars <- sim$parameters[sim$parameters$parameter == "equipment_power_density", ]
#' runs <- simulate_design(sim, design_lhs(pars, 8, seed = 1))
#' bills <- function(k) data.frame(y = seb_field$y * k, sim$x)
#' buildings <- data.frame(id = c("a", "b"))
#' buildings$field <- list(bills(1), bills(0.9))
#' buildings$runs <- list(runs, runs)
#' buildings$simulator <- list(sim, sim)
#' p <- calibrate_portfolio(buildings, file.path(tempdir(), "portfolio"), chains = 2,
#'                          retrofit = function(s) scenario(s, scale = c(equipment_power_density = 0.7)),
#'                          ndraws = 10)
#' summary(p)
#' }
calibrate_portfolio <- function(buildings, dir, retrofit = NULL, ndraws = 40, seed = 1L,
                                keep_fits = FALSE, ...) {
  buildings <- check_portfolio_table(buildings, retrofit)
  if (!is.null(retrofit) && !is.function(retrofit)) {
    abort_bayesbem("{.arg retrofit} must be a function of a simulator giving a {.fn scenario}, not {describe_value(retrofit)}.",
                   "argument")
  }
  check_count(ndraws)
  check_count(seed)
  check_bool(keep_fits)
  check_string(dir)
  dir.create(dir, recursive = TRUE, showWarnings = FALSE)
  if (!dir.exists(dir) || file.access(dir, 2L) != 0L) {
    abort_bayesbem(c("{.arg dir} must be a folder the results can be written to.",
                     x = "{.file {dir}} could not be created or is not writable."),
                   "argument")
  }
  seeds <- buildings$seed %||% (seed + seq_len(nrow(buildings)) - 1L)
  pending <- which(!vapply(buildings$id, portfolio_done, logical(1), dir = dir))
  options <- list(...)
  check_portfolio_options(options)
  sent <- pending[vapply(pending, function(i) portfolio_check(buildings[i, ], dir, options),
                         logical(1))]
  inform_portfolio(nrow(buildings), pending, sent)
  progress <- progressr::progressor(along = sent)
  old_seed <- saved_seed()
  on.exit(restore_seed(old_seed), add = TRUE)
  future.apply::future_lapply(sent, function(i) {
    record <- portfolio_job(buildings[i, ], seeds[i], retrofit, ndraws, keep_fits, options)
    write_record(record, dir)
    progress()
    NULL
  }, future.seed = TRUE, future.packages = "bayesbem")
  read_portfolio(dir, buildings$id)
}

# The buildings table, checked: unique file-safe ids, a field table of one
# output each, and runs or a simulator with its design each.
check_portfolio_table <- function(buildings, retrofit, call = rlang::caller_env()) {
  if (!is.data.frame(buildings) || nrow(buildings) == 0L || !is.list(buildings$field)) {
    abort_bayesbem(c("{.arg buildings} must be a data frame with a row per building and a list column {.field field}, not {describe_value(buildings)}.",
                     i = "Columns: {.field id}, {.field field}, and {.field runs} or {.field simulator} with {.field design}."),
                   "argument", call = call)
  }
  id <- buildings$id
  if (!is.character(id) || anyNA(id) || anyDuplicated(id) || any(!grepl("^[A-Za-z0-9._-]+$", id))) {
    abort_bayesbem(c("{.field id} must be unique names of letters, digits, {.val .}, {.val _} or {.val -} (they name the result files).",
                     x = "It is {describe_value(id)}."),
                   "argument", call = call)
  }
  has_runs <- is.list(buildings$runs)
  has_design <- is.list(buildings$simulator) && is.list(buildings$design)
  if (!has_runs && !has_design) {
    abort_bayesbem("{.arg buildings} needs a list column {.field runs}, or {.field simulator} and {.field design}.",
                   "argument", call = call)
  }
  if (!is.null(retrofit) && !is.list(buildings$simulator)) {
    abort_bayesbem("With {.arg retrofit}, {.arg buildings} needs a list column {.field simulator}: the retrofit is a scenario of each building's simulator.",
                   "argument", call = call)
  }
  if (!is.null(buildings$seed)) lapply(buildings$seed, check_count, arg = "seed", call = call)
  several <- buildings$id[vapply(buildings$field, function(f) {
    inherits(f, "bayesbem_outputs") || "output" %in% names(f)
  }, logical(1))]
  if (length(several) > 0L) {
    abort_bayesbem(c("A building's {.field field} must hold one output: {.val {several}} {?holds/hold} several (an {.field output} column).",
                     i = "Give each meter as a building (row) of its own; the portfolio's table reports one output's metrics and savings per row."),
                   "argument", call = call)
  }
  buildings
}

# Whether building `id` has a finished result in `dir`.
portfolio_done <- function(id, dir) {
  path <- record_path(id, dir)
  file.exists(path) && identical(readRDS(path)$status, "done")
}

record_path <- function(id, dir) file.path(dir, paste0(id, ".rds"))

# Writes a building's record whole or not at all: to a temporary name in
# the same directory, then renamed (atomic on one file system).
write_record <- function(record, dir) {
  path <- record_path(record$id, dir)
  temporary <- tempfile(paste0(record$id, "-"), tmpdir = dir, fileext = ".part")
  saveRDS(record, temporary)
  if (!file.rename(temporary, path)) {
    unlink(temporary)
    abort_bayesbem("Could not write {.file {path}}.", "portfolio")
  }
  invisible(path)
}

# calibrate()'s checks before sampling, for a building whose runs are
# given; a building that fails them is recorded as refused (FALSE: not to
# be sent).
portfolio_check <- function(building, dir, options) {
  if (is.null(building$runs[[1]])) {
    return(TRUE)
  }
  checked <- tryCatch({
    suppressMessages(do.call(calibration_spec_of, c(list(building$field[[1]], building$runs[[1]]),
                                                    options)))
    NULL
  }, error = function(e) e)
  if (is.null(checked)) {
    return(TRUE)
  }
  write_record(failed_record(building$id, checked, "refused"), dir)
  FALSE
}

# calibrate()'s arguments that calibrate_portfolio() sets for each job
# refused in `...` (the building's data and runs, and the progress bar:
# one bar counts the buildings).
check_portfolio_options <- function(options, call = rlang::caller_env()) {
  own <- intersect(names(options), c("field", "sim", "progress"))
  if (length(own) > 0L) {
    abort_bayesbem(c("{.arg {own}} {?is/are} set by {.fn calibrate_portfolio} for each building, not passed to {.fn calibrate}.",
                     i = "Give each building's data and runs in {.arg buildings}; one progress bar counts the buildings."),
                   "argument", call = call)
  }
}

# calibration_spec() with calibrate()'s defaults for the settings `...`
# leaves out; what calibrate() does not name goes on as rstan's arguments.
calibration_spec_of <- function(field, sim, ...) {
  given <- list(...)
  settings <- setdiff(names(formals(calibration_spec)), c("field", "sim", "dots", "call"))
  args <- lapply(formals(calibrate)[settings], eval, envir = environment(calibrate))
  chosen <- intersect(names(given), settings)
  args[chosen] <- given[chosen]
  dots <- given[setdiff(names(given), names(formals(calibrate)))]
  do.call(calibration_spec, c(list(field, sim), args, list(dots = dots)))
}

failed_record <- function(id, error, status = "failed") {
  list(id = id, status = status, error = conditionMessage(error),
       error_class = class(error)[1])
}

# One building's pipeline, its errors caught into its record and its
# warnings (convergence, range limits) kept there. Seeded at the start, so
# that what it draws besides the fit's own seeded sampling (the metrics'
# and the savings' draws) is the same under any plan.
portfolio_job <- function(building, seed, retrofit, ndraws, keep_fits, options) {
  set.seed(seed)
  started <- proc.time()[["elapsed"]]
  warnings <- character()
  keep_warning <- function(w) {
    warnings <<- c(warnings, conditionMessage(w))
    invokeRestart("muffleWarning")
  }
  record <- tryCatch(withCallingHandlers({
    runs <- building$runs[[1]] %||%
      simulate_design(building$simulator[[1]], building$design[[1]])
    fit <- do.call(calibrate, c(list(building$field[[1]], runs, seed = seed, progress = FALSE),
                                options))
    c(list(id = building$id, status = "done"), building_results(fit),
      if (!is.null(retrofit)) building_savings(fit, building$simulator[[1]], retrofit, ndraws),
      if (keep_fits) list(fit = fit))
  }, warning = keep_warning), error = function(e) failed_record(building$id, e))
  record$warnings <- warnings
  record$seconds <- proc.time()[["elapsed"]] - started
  record
}

# What the portfolio's table reports of one fit.
building_results <- function(fit) {
  convergence <- check_convergence(fit, warn = FALSE)
  sampler <- attr(convergence, "sampler")
  metrics <- calibration_metrics(fit)
  calibrated <- metrics[metrics$prediction == "calibrated", ]
  field <- fit$data$field
  time <- Filter(function(v) inherits(v, "POSIXct"), field)
  list(rhat = max(convergence$rhat), ess_bulk = min(convergence$ess_bulk),
       divergent = sum(sampler$divergent), converged = all(convergence$ok) &&
         sum(sampler$divergent) == 0L,
       cvrmse = calibrated$cvrmse[1], nmbe = calibrated$nmbe[1],
       sufficiency = if (length(time) > 0L) min(data_sufficiency(time[[1]])$share) else NA_real_,
       verdict = attr(discrepancy(fit, ndraws = 100), "verdict"))
}

# The savings of a building's retrofit: the draws of the total (paired
# baseline and retrofit) and Guideline 14's FSU of the same level.
building_savings <- function(fit, simulator, retrofit, ndraws) {
  saved <- savings(fit, scenario(simulator), retrofit(simulator), ndraws = ndraws)
  total <- rowSums(saved$savings)
  baseline <- mean(rowSums(saved$baseline))
  list(savings_draws = total, baseline = baseline,
       fsu_guideline14 = guideline14_fsu(fit, ncol(saved$savings), abs(mean(total)) / baseline,
                                         0.9),
       guideline14_df = fit$data$n - 1L)
}

# Which buildings are sent, said once.
inform_portfolio <- function(n, pending, sent) {
  done <- n - length(pending)
  refused <- length(pending) - length(sent)
  cli::cli_inform(c(i = paste0("{length(sent)} of {n} building{?s} to calibrate",
                               "{if (done > 0) paste0('; ', done, ' already done') else ''}",
                               "{if (refused > 0) paste0('; ', refused, ' refused before sending (see summary())') else ''}.")),
                  class = "bayesbem_message_portfolio")
}

# The records of buildings `ids` in `dir`, as a bayesbem_portfolio.
read_portfolio <- function(dir, ids) {
  records <- lapply(ids, function(id) {
    path <- record_path(id, dir)
    if (file.exists(path)) readRDS(path) else list(id = id, status = "missing")
  })
  structure(list(dir = dir, records = stats::setNames(records, ids)),
            class = "bayesbem_portfolio")
}
