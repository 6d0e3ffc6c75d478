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
#'   runs left out), and an attribute `failed`: a data frame with the
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
  rows <- lapply(which(ok), function(i) {
    data.frame(eta = runs[[i]]$value, x, design[rep(i, nrow(x)), , drop = FALSE],
               row.names = NULL, check.names = FALSE)
  })
  out <- if (length(rows) > 0L) do.call(rbind, rows) else
    data.frame(eta = numeric(), x[0, , drop = FALSE], design[0, , drop = FALSE])
  attr(out, "failed") <- failed
  out
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

check_run_output <- function(value, n) {
  if (!is.numeric(value) || length(value) != n) {
    return(sprintf("the simulator returned %s of length %d, not %d numbers",
                   class(value)[1], length(value), n))
  }
  if (any(!is.finite(value))) {
    return("the simulator returned missing or non-finite values")
  }
  NULL
}
