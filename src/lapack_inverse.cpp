// Sigma^-1 and log|Sigma| by R's LAPACK, for normal_two_kernels_lpdf()
// (inst/include/normal_two_kernels.hpp). That header is included inside each
// Stan model's namespace, where R's headers cannot go; it declares this
// function with C linkage, which names the one defined here.
//
// R's LAPACK runs on the BLAS R is linked to: with an optimised BLAS
// (OpenBLAS, MKL, BLIS, Accelerate) a stage-2 gradient at n = 365 takes
// less than half of Eigen's time, with the reference BLAS three times
// Eigen's (bench/results/), hence the choice in R (use_lapack(),
// R/utils-lapack.R).
#define USE_FC_LEN_T
#include <R_ext/BLAS.h>
#include <R_ext/Lapack.h>
#include <cmath>

// The n x n lower triangle at a (leading dimension lda) is overwritten by
// its inverse, by halves (the recursive TRTRI of ReLAPACK: Peise &
// Bientinesi 2017, ACM TOMS 44(2)):
//   [L11 0; L21 L22]^-1 = [L11^-1 0; -L22^-1 L21 L11^-1  L22^-1],
// the diagonal halves inverted first, then L21 multiplied by them (dtrmm).
// Nearly all the flops are then in dtrmm: at n = 365 on OpenBLAS 0.3.21
// this takes a third of the time of OpenBLAS's own dtrtri
// (inst/notes/decisions/S7-a-hand-written-gradient-for-the.md).
static int invert_lower(int n, double* a, int lda) {
  int info = 0;
  if (n <= 16) {
    F77_CALL(dtrtri)("L", "N", &n, a, &lda, &info FCONE FCONE);
    return info;
  }
  int n1 = n / 2, n2 = n - n1;
  double one = 1, minus_one = -1;
  double* a11 = a;
  double* a21 = a + n1;
  double* a22 = a + n1 + static_cast<long>(n1) * lda;
  if ((info = invert_lower(n1, a11, lda)) != 0) {
    return info;
  }
  if ((info = invert_lower(n2, a22, lda)) != 0) {
    return info + n1;
  }
  F77_CALL(dtrmm)("R", "L", "N", "N", &n2, &n1, &one, a11, &lda, a21, &lda
                  FCONE FCONE FCONE FCONE);
  F77_CALL(dtrmm)("L", "L", "N", "N", &n2, &n1, &minus_one, a22, &lda, a21, &lda
                  FCONE FCONE FCONE FCONE);
  return 0;
}

// a: the n x n symmetric positive-definite matrix, column-major, its lower
// triangle read. On return its lower triangle holds the lower triangle of
// a^-1 (the strict upper triangle is left as it was) and log_det is log|a|.
// Returns LAPACK's info: 0 on success, > 0 when a is not positive definite.
// What dpotri does, with the triangular inverse above: a = L L' (dpotrf),
// L^-1, then a^-1 = L^-T L^-1 (dlauum).
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
  if ((info = invert_lower(n, a, n)) != 0) {
    return info;
  }
  F77_CALL(dlauum)("L", &n, a, &n, &info FCONE);
  return info;
}
