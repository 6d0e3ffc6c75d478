# Runs the test suite against the installed package and ends with one line
# "N passed, N failed, N skipped" (expectations); exits 1 on any failure.
# Usage, from the package root: Rscript tools/run-tests.R [filter]
# (`filter`: a regular expression on the test files' names, as testthat's).
# BAYESBEM_TEST_TIMES=<file> writes each test's seconds there (a CSV).
Sys.setenv(NOT_CRAN = "true")
# report every failure (the progress reporter stops after 10 by default)
options(testthat.progress.max_fails = Inf)
# EnergyPlus tests use the project's shared build when no other is configured
shared_eplus <- file.path("..", "shared", "energyplus")
if (!nzchar(Sys.getenv("BAYESBEM_EPLUS")) && dir.exists(shared_eplus)) {
  Sys.setenv(BAYESBEM_EPLUS = normalizePath(shared_eplus))
}
# Two test processes (testthat's parallel mode), the longest files first
# (DESCRIPTION's Config/testthat/start-first) so that neither waits on the
# other at the end; TESTTHAT_PARALLEL=false runs them in this process.
if (!nzchar(Sys.getenv("TESTTHAT_PARALLEL"))) Sys.setenv(TESTTHAT_PARALLEL = "true")
filter <- commandArgs(trailingOnly = TRUE)[1]
results <- testthat::test_dir("tests/testthat", filter = if (!is.na(filter)) filter,
                              package = "bayesbem",
                              load_package = "installed", stop_on_failure = FALSE,
                              reporter = testthat::ProgressReporter$new(show_praise = FALSE))
outcomes <- unlist(lapply(results, function(test) {
  vapply(test$results, function(e) class(e)[1], character(1))
}))
passed <- sum(outcomes == "expectation_success")
failed <- sum(outcomes %in% c("expectation_failure", "expectation_error"))
skipped <- sum(outcomes == "expectation_skip")
times_file <- Sys.getenv("BAYESBEM_TEST_TIMES")
if (nzchar(times_file)) {
  times <- as.data.frame(results)[c("file", "test", "real")]
  utils::write.csv(times[order(-times$real), ], times_file, row.names = FALSE)
}
cat(sprintf("\n%d passed, %d failed, %d skipped\n", passed, failed, skipped))
quit(status = if (failed > 0L) 1L else 0L)
