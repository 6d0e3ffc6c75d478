# The seed of every model fit in the tests: the number the test was written
# with plus an offset from the environment variable BAYESBEM_TEST_SEED (0 by
# default). Running the suite under several offsets shows that a test
# asserts what holds for any converged fit, not what one sampler trajectory
# gave (CONTRIBUTING, "Tests").
test_seed <- function(seed) {
  offset <- Sys.getenv("BAYESBEM_TEST_SEED", "0")
  if (!grepl("^[0-9]+$", offset)) {
    stop("BAYESBEM_TEST_SEED must be a whole number, not \"", offset, "\".", call. = FALSE)
  }
  seed + as.integer(offset)
}
