# Which library factors the n x n field covariance in the grid and modular
# Stan programs (normal_two_kernels_lpdf(), inst/include/normal_two_kernels.hpp):
# R's LAPACK or Eigen. The factor and inverse are the largest part of a
# gradient at large n (1.5 of 2.1 ms at n = 365 on OpenBLAS). R's LAPACK
# runs on the BLAS R is linked to: with an optimised one (OpenBLAS, MKL,
# BLIS, ATLAS, Apple's Accelerate) the stage-2 gradient at n = 365 takes
# 2.1 ms against Eigen's 4.3-5.1; with the reference BLAS, which R ships by
# default, 15-16 ms against Eigen's 4.5 (bench/RESULTS.md). The choice is made
# from R's BLAS, not timed, so that a seeded fit is repeatable on a machine.
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
