// Sigma^-1 and log|Sigma| by R's LAPACK, for normal_two_kernels_lpdf()
// (inst/include/normal_two_kernels.hpp). That header is included inside each
// Stan model's namespace, where R's headers cannot go; it declares this
// function with C linkage, which names the one defined here.
//
// R's LAPACK runs on the BLAS R is linked to: with an optimised BLAS
// (OpenBLAS, MKL, BLIS, Accelerate) dpotrf + dpotri at n = 365 take about
// half of Eigen's time, with the reference BLAS four to six times Eigen's
// (bench/RESULTS.md), hence the choice in R (use_lapack(), R/utils-lapack.R).
#define USE_FC_LEN_T
#include <R_ext/Lapack.h>
#include <cmath>

// a: the n x n symmetric positive-definite matrix, column-major, its lower
// triangle read. On return its lower triangle holds the lower triangle of
// a^-1 (the strict upper triangle is left as it was) and log_det is log|a|.
// Returns LAPACK's info: 0 on success, > 0 when a is not positive definite.
extern "C" int bayesbem_lapack_inverse(int n, double* a, double* log_det) {
  int info = 0;
  F77_CALL(dpotrf)("L", &n, a, &n, &info FCONE);
  if (info != 0) {
    return info;
  }
  double half = 0;
  for (int i = 0; i < n; ++i) {
    half += std::log(a[i + static_cast<long>(i) * n]);
  }
  *log_det = 2 * half;
  F77_CALL(dpotri)("L", &n, a, &n, &info FCONE);
  return info;
}
