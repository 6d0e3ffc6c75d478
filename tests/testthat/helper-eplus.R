# EnergyPlus tests run when EnergyPlus is found (tools/run-tests.R points
# BAYESBEM_EPLUS to the project's shared build) and skip otherwise.
skip_if_no_eplus <- function() {
  if (!eplus_available()) {
    testthat::skip("EnergyPlus not found: set BAYESBEM_EPLUS to its directory to run this test")
  }
}

# The shipped model's EnergyPlus simulator on the 2013 weather.
seb_eplus <- function(...) {
  eplus_simulator(weather = shipped_epw(2013), ...)
}

seb_model <- function() {
  eplus_model(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
}

# A model of the shared EnergyPlus folder's examples (skips when absent).
example_model_path <- function(file) {
  skip_if_no_eplus()
  path <- file.path(eplus_path(), "examples", file)
  if (!file.exists(path)) testthat::skip(paste("no", path))
  path
}

# Annual totals of a simulation table, by run.
run_totals <- function(table, runs) {
  as.vector(tapply(table$eta, rep(seq_len(runs), each = nrow(table) / runs), sum))
}

# Runs of the calling test on two local workers (EnergyPlus runs are
# processes of their own; the suite's R process only waits on them).
local_eplus_workers <- function(env = parent.frame()) {
  withr::local_options(future.rng.onMisuse = "ignore", .local_envir = env)
  future::plan(future::multisession, workers = 2)
  withr::defer(future::plan(future::sequential), envir = env)
}
