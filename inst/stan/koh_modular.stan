// Stage 2 of the modular KOH fit (Liu, Bayarri & Berger 2009) on a grid
// design: the calibration parameters, the discrepancy and the noise, with
// the emulator's hyperparameters fixed at their stage-1 estimates
// (koh_emulator.stan). Everything that depends on the emulator alone is
// data: the runs less the emulator mean at the field inputs, E_f, the field
// block of Kx and the Cholesky factor of Kt. Each gradient then costs one
// Cholesky factor and one inverse of an n x n matrix, in C++ with the
// analytic gradient, O(n^3 + n mt + mt^2). The log density is that of
// koh_grid.stan given the runs, at the fixed emulator.
//
// Several outputs (meters) share the calibration parameters tf; each has
// its own emulator, discrepancy and noise, and given tf the outputs are
// independent, so the likelihood is the sum of each output's (its rows are
// a block of the stacked data) and a gradient costs the sum of theirs.
// With one output this is the one-output model, term by term.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
  // where each output's block of the stacked rows starts, its size, its discrepancy terms
#include /include/koh_outputs.stan
}
data {
  // n, mt, p, q, K; y, xf, tc, each row's output and noise weight
#include /include/koh_stage2_data.stan
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  int<lower=0, upper=1> lapack;          // Sigma factored by R's LAPACK (1) or Eigen (0)
  // the stage-1 emulator of each output, one column per output
#include /include/koh_stage2_emulators.stan
  int<lower=1> n_max;                    // rows of the largest output
  matrix[n, mt] E_f;                     // runs at the field inputs less the emulator mean
  matrix[n, n_max] Kx_ff;                // jittered correlation of each output's field inputs
  matrix[K * mt, mt] Lt;                 // Cholesky factor of each output's jittered Kt
}
transformed data {
  matrix[1 + p + q, K] coef;
  for (k in 1:K) {
    coef[, k] = mean_coefficients(b_select, col(b_fixed, k));
  }
}
parameters {
  vector<lower=0, upper=1>[q] tf;        // calibration parameters
  // rho_delta, lambda_delta, lambda_e (each output's), gamma
#include /include/koh_stage2_parameters.stan
}
transformed parameters {
  vector[p * K] beta_delta = -4 * log(rho_delta);
}
model {
  matrix[mt + 1, K] wc;                  // runs_weights() of each output at tf
  for (k in 1:K) {
    wc[, k] = runs_weights(block(Lt, (k - 1) * mt + 1, 1, mt, mt),
                           tf_cor(tf', tc, tail(col(beta_eta_fixed, k), q)), nugget);
  }
  // priors of the calibration parameters, the discrepancy and the noise
#include /include/koh_stage2_priors.stan
  for (k in 1:K) {
    int s = output_start(output, k);
    int len = output_size(output, k);
    target += normal_two_kernels_lpdf(segment(y, s, len)
                                      - emulator_mean(block(xf, s, 1, len, p), rep_matrix(tf', len),
                                                      col(coef, k))
                                      - output_terms(h, gamma, s, len)
                                      - block(E_f, s, 1, len, mt) * head(col(wc, k), mt)
                                      | block(Kx_ff, s, 1, len, len),
                                      wc[mt + 1, k] / lambda_eta_fixed[k], block(xf, s, 1, len, p),
                                      segment(beta_delta, (k - 1) * p + 1, p), lambda_delta[k],
                                      segment(noise_weight, s, len) / lambda_e[k], lapack);
  }
}
generated quantities {
  // the fixed emulators, under the names of the joint programs (output
  // k's beta_eta and b are its block of p + q and of n_b elements)
#include /include/koh_fixed_emulator.stan
}
