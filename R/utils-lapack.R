# Which library factors the n x n field covariance in the grid and modular
# Stan programs (normal_two_kernels_lpdf(), inst/include/normal_two_kernels.hpp):
# R's LAPACK or Eigen. The factor and inverse are the largest part of a
# gradient at large n, and R's LAPACK runs on the BLAS R is linked to:
# faster than Eigen on an optimised one (OpenBLAS, MKL, BLIS, ATLAS, Apple's
# Accelerate), slower on the reference BLAS R ships by default
# (bench/results/gradient.md). The choice is made from R's BLAS,
# not timed, so that a seeded fit is repeatable on a machine.
# The option `bayesbem.lapack` (TRUE or FALSE) overrides it.
use_lapack <- function(call = rlang::caller_env()) {
  choice <- getOption("bayesbem.lapack", "auto")
  if (identical(choice, "auto")) {
    return(optimised_blas(extSoftVersion()[["BLAS"]]))
  }
  if (!rlang::is_bool(choice)) {
    abort_bayesbem(c("The option {.code bayesbem.lapack} must be {.code TRUE}, {.code FALSE} or {.val auto}, not {describe_value(choice)}.",
                     i = "Reset it with {.code options(bayesbem.lapack = NULL)}."),
                   "option", call = call)
  }
  choice
}

# Whether the BLAS library at path `blas` (extSoftVersion()[["BLAS"]]) is an
# optimised one, by its name.
optimised_blas <- function(blas) {
  grepl("openblas|mkl|blis|atlas|accelerate|veclib", blas, ignore.case = TRUE)
}

# Tells once per session, when a fit with a large field covariance (the grid
# and modular programs at more than 120 field rows) runs on Eigen because
# R's BLAS is not a known optimised one (optimised_blas()), that an
# optimised BLAS would be faster (bench/results/gradient.md).
# Silent when the user chose
# the path with the option `bayesbem.lapack`.
inform_blas <- function(n, lapack, field_density) {
  if (lapack || !field_density || n <= 120 ||
      !identical(getOption("bayesbem.lapack", "auto"), "auto")) {
    return(invisible())
  }
  blas <- extSoftVersion()[["BLAS"]]
  cli::cli_inform(c(i = "{n} field rows: each gradient factors a {n} x {n} matrix, here by Eigen, since R's BLAS ({.path {blas}}) is not a known optimised one.",
                    " " = "With R linked to OpenBLAS (on Debian or Ubuntu, {.code apt install libopenblas0-serial}) it runs on R's LAPACK, faster; see {.code ?calibrate}, \"Linear algebra\"."),
                  class = "bayesbem_message_blas", .frequency = "once",
                  .frequency_id = "bayesbem_blas")
}
