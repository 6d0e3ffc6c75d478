// Stage 2 of the modular KOH fit (Liu, Bayarri & Berger 2009) on a grid
// design: the calibration parameters, the discrepancy and the noise, with
// the emulator's hyperparameters fixed at their stage-1 estimates
// (koh_emulator.stan). Everything that depends on the emulator alone is
// data: the runs less the emulator mean at the field inputs, E_f, the field
// block of Kx and the Cholesky factor of Kt. Each gradient then costs one
// Cholesky factor and one inverse of an n x n matrix, in C++ with the
// analytic gradient, O(n^3 + n mt + mt^2). The log density is that of
// koh_grid.stan given the runs, at the fixed emulator.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
}
data {
  // n, mt, p, q; y, xf and tc
#include /include/koh_stage2_data.stan
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  int<lower=0, upper=1> lapack;          // Sigma factored by R's LAPACK (1) or Eigen (0)
  // the stage-1 emulator
  vector[p + q] beta_eta_fixed;          // its correlation parameters
  real<lower=0> lambda_eta_fixed;        // its precision
  vector[n_b] b_fixed;                   // its mean coefficients
  matrix[n, mt] E_f;                     // runs at the field inputs less the emulator mean
  matrix[n, n] Kx_ff;                    // jittered correlation of the field inputs
  matrix[mt, mt] Lt;                     // Cholesky factor of the jittered run correlation
}
transformed data {
  vector[1 + p + q] coef = mean_coefficients(b_select, b_fixed);
}
parameters {
  vector<lower=0, upper=1>[q] tf;        // calibration parameters
  // rho_delta, lambda_delta, lambda_e, gamma
#include /include/koh_stage2_parameters.stan
}
transformed parameters {
  vector[p] beta_delta = -4 * log(rho_delta);
}
model {
  vector[mt + 1] wc = runs_weights(Lt, tf_cor(tf', tc, tail(beta_eta_fixed, q)), nugget);
  // priors of the calibration parameters, the discrepancy and the noise
#include /include/koh_stage2_priors.stan
  target += normal_two_kernels_lpdf(y - emulator_mean(xf, rep_matrix(tf', n), coef)
                                    - discrepancy_terms(h, gamma) - E_f * head(wc, mt)
                                    | Kx_ff, wc[mt + 1] / lambda_eta_fixed, xf, beta_delta,
                                    lambda_delta, 1 / lambda_e, lapack);
}
generated quantities {
  // the fixed emulator, under the names of the joint programs
#include /include/koh_fixed_emulator.stan
}
