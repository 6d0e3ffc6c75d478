#' Run a simulator at every point of a design
#'
#' Runs the simulator once per row of `design` and returns the simulation
#' table `[eta, x, t]` that [calibrate()] takes: for each run, one row per
#' field period with the simulated output `eta`, the period's observable
#' inputs `x`, and the run's parameter values `t` (the design's columns).
#'
#' Runs go through [future.apply::future_lapply()], so the [future::plan()]
#' decides where they run: sequentially by default, on all cores with
#' `future::plan(future::multisession)`, or on a cluster scheduler with a
#' `future.batchtools` plan. Progress is reported through progressr (wrap the
#' call in [progressr::with_progress()]). A run that fails is reported by
#' row with its error message in a warning of class
#' `bayesbem_warning_simulation` and in the attribute `failed` of the
#' result; the other runs are kept. With a `cache_dir`, every successful
#' run is saved there under a hash of everything that determines its output
#' (the simulator's key, see [simulator()], its inputs and the run's
#' parameter values), so calling again with the same arguments only repeats
#' the failed runs, and a changed simulator never gets another's results.
#'
#' @param simulator A `bayesbem_simulator` (see [simulator()],
#'   [bem_simulator()]).
#' @param design A data frame of parameter settings, one row per run, one
#'   column per varied parameter (physical units), e.g. from [design_lhs()].
#' @param cache_dir Optional directory for cached run results.
#' @return A data frame with columns `eta`, the observable inputs and the
#'   design's parameters, with `nrow(design) * nrow(x)` rows (runs of failed
#'   runs left out); for a simulator of several outputs, a first column
#'   `output` naming each row's output, and a row per output and period of
#'   each run; and an attribute `failed`: a data frame with the
#'   `run` (row of `design`) and `error` of each failed run.
#' @family simulation
#' @export
#' @examples
#' sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' design <- design_lhs(bem_parameters()[12:13, ], n = 4, seed = 1)
#' head(simulate_design(sim, design))
simulate_design <- function(simulator, design, cache_dir = NULL) {
  if (!inherits(simulator, "bayesbem_simulator")) {
    abort_bayesbem(c("{.arg simulator} must be a simulator.",
                     i = "Make one with {.fn simulator} or {.fn bem_simulator}."),
                   "argument")
  }
  settings <- design_settings(simulator, design)
  if (!is.null(cache_dir)) dir.create(cache_dir, showWarnings = FALSE, recursive = TRUE)
  key <- simulator_key(simulator)
  progress <- progressr::progressor(along = settings)
  # future.seed = TRUE leaves the session on L'Ecuyer-CMRG: keep the caller's
  # generator as it was
  old_seed <- saved_seed()
  on.exit(restore_seed(old_seed), add = TRUE)
  runs <- future.apply::future_lapply(settings, function(params) {
    result <- run_cached(simulator, key, params, cache_dir)
    progress()
    result
  }, future.seed = TRUE)
  ok <- vapply(runs, function(r) is.null(r$error), logical(1))
  failed <- data.frame(run = which(!ok),
                       error = vapply(runs[!ok], `[[`, character(1), "error"))
  if (nrow(failed) > 0L) {
    warn_bayesbem(c("{nrow(failed)} of {length(runs)} simulation run{?s} failed; the others are kept.",
                    stats::setNames(sprintf("run %d: %s", failed$run, failed$error),
                                    rep("x", nrow(failed))),
                    i = "See {.code attr(result, \"failed\")}; with {.arg cache_dir}, calling again repeats only the failed runs."),
                  "simulation")
  }
  x <- simulator$x
  check_same_outputs_runs(runs[ok])
  rows <- lapply(which(ok), function(i) {
    run_rows(runs[[i]]$value, x, design[rep(i, nrow(x)), , drop = FALSE])
  })
  out <- if (length(rows) > 0L) do.call(rbind, rows) else
    data.frame(eta = numeric(), x[0, , drop = FALSE], design[0, , drop = FALSE])
  attr(out, "failed") <- failed
  out
}

# The rows of one run: `eta` at each period, or, for a run of several
# outputs, each output's rows in turn with the `output` column naming it.
run_rows <- function(value, x, settings) {
  if (!is.data.frame(value)) {
    return(data.frame(eta = value, x, settings, row.names = NULL, check.names = FALSE))
  }
  do.call(rbind, lapply(names(value), function(k) {
    data.frame(output = k, eta = value[[k]], x, settings, row.names = NULL, check.names = FALSE)
  }))
}

# The runs of one design give the same outputs.
check_same_outputs_runs <- function(runs, call = rlang::caller_env()) {
  if (length(runs) == 0L) {
    return(invisible())
  }
  outputs <- lapply(runs, function(r) names(r$value))
  differ <- which(!vapply(outputs, identical, logical(1), outputs[[1]] %||% NULL))
  if (length(differ) > 0L) {
    abort_bayesbem(c("The simulator returned other outputs in some runs.",
                     x = "The first run gave {.val {outputs[[1]] %||% 'one output'}}, run {differ[1]} {.val {outputs[[differ[1]]] %||% 'one output'}}.",
                     i = "A simulator returns the same outputs (a vector, or the same named columns) in every run."),
                   "simulation", call = call)
  }
}

# One run, from the cache when it holds it (under a hash of the simulator's
# key, its inputs and the parameters); errors are returned, not thrown.
run_cached <- function(simulator, key, params, cache_dir) {
  path <- if (!is.null(cache_dir)) {
    file.path(cache_dir, paste0(rlang::hash(list(key, simulator$x, params)), ".rds"))
  }
  if (!is.null(path) && file.exists(path)) {
    return(list(value = readRDS(path), error = NULL))
  }
  value <- tryCatch(simulator$fun(params, simulator$x), error = function(e) e)
  error <- if (inherits(value, "error")) conditionMessage(value) else
    check_run_output(value, nrow(simulator$x))
  if (!is.null(error)) {
    return(list(value = NULL, error = error))
  }
  if (!is.null(path)) saveRDS(value, path)
  list(value = value, error = NULL)
}

# NULL when a run's value is one number per period, or a data frame of
# them with a named column per output; else what is wrong.
check_run_output <- function(value, n) {
  if (is.data.frame(value)) {
    names <- names(value)
    if (length(names) == 0L || anyNA(names) || any(!nzchar(names)) || anyDuplicated(names)) {
      return("the simulator returned a data frame without a unique name for each output column")
    }
    problems <- unlist(lapply(value, check_run_output, n = n))
    return(if (nrow(value) != n) sprintf("the simulator returned %d rows, not %d", nrow(value), n) else
      problems[1])
  }
  if (!is.numeric(value) || length(value) != n) {
    return(sprintf("the simulator returned %s of length %d, not %d numbers",
                   class(value)[1], length(value), n))
  }
  if (any(!is.finite(value))) {
    return("the simulator returned missing or non-finite values")
  }
  NULL
}
