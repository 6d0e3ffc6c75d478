// Kennedy-O'Hagan calibration on a grid design: every one of the mt runs is
// made at the field inputs (x_c = x_f; field rows sharing their inputs
// share a grid input) and possibly at further inputs, e.g. of held-out
// periods (n_x in all). The log density equals koh.stan's,
// but the emulator covariance is the Kronecker product Kt (x) Kx, so each
// gradient costs O(mt^3 + n^3) instead of O((n (mt + 1))^3).
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
}
data {
  int<lower=1> n;                        // field observations
  int<lower=1> n_x;                      // grid inputs: the distinct field inputs first
  int<lower=1> mt;                       // simulation runs
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  vector[n] y;                           // field output
  matrix[n_x, mt] eta;                   // simulator output of run a at grid input i
  matrix[n_x, p] x_grid;                 // grid inputs, shared by every run
  matrix[mt, q] tc;                      // simulation design, one row per run
  matrix[n, p] xf;                       // each field row's grid input
  matrix[n, mt] eta_f;                   // the runs at each field row's grid input
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  int<lower=0, upper=1> lapack;          // Sigma factored by R's LAPACK (1) or Eigen (0)
  vector<lower=0>[n] noise_weight;       // each field row's noise variance relative to 1 / lambda_e
}
transformed data {
  matrix[n * n, p + 1] nd2_ff = neg_sqdist(xf, xf);
  matrix[n, n] eq_ff = equal_rows(xf, xf);
  matrix[n_x * n_x, p + 1] nd2_xx = neg_sqdist(x_grid, x_grid);
  matrix[mt * mt, q + 1] nd2_tt = neg_sqdist(tc, tc);
  matrix[n_x, n_x] eq_xx = equal_rows(x_grid, x_grid);
  matrix[mt, mt] eq_tt = equal_rows(tc, tc);
}
parameters {
  // tf, rho_eta, rho_delta, lambda_eta, lambda_delta, lambda_e, gamma, b
#include /include/koh_parameters.stan
}
transformed parameters {
  // beta_eta and beta_delta, the correlation parameters on the log scale
#include /include/koh_transformed_parameters.stan
}
model {
  vector[1 + p + q] coef = mean_coefficients(b_select, b);
  matrix[n_x, n_x] Kx = jittered_cor(nd2_xx, eq_xx, head(beta_eta, p), nugget);
  matrix[mt, mt] Kt = jittered_cor(nd2_tt, eq_tt, tail(beta_eta, q), nugget);
  vector[mt] k0 = tf_cor(tf', tc, tail(beta_eta, q));
  // the priors of every parameter
#include /include/koh_priors.stan
  // the Gaussian processes model what the emulator mean and the discrepancy
  // terms leave: eta - h(x, t)' b at the runs, y - h(xf, tf)' b - h' gamma.
  // The log density is that of koh.stan without forming its covariance: the
  // runs' Kronecker density times the field outputs' density given the runs.
  {
    matrix[n_x, mt] E = eta - grid_mean(x_grid, tc, coef);
    matrix[mt, mt] Lt = cholesky_decompose(Kt);
    vector[mt + 1] wc = runs_weights(Lt, k0, nugget);
    target += runs_grid_lpdf(E | cholesky_decompose(Kx), Lt, lambda_eta);
    target += normal_two_kernels_lpdf(y - emulator_mean(xf, rep_matrix(tf', n), coef)
                                      - discrepancy_terms(h, gamma)
                                      - (eta_f - grid_mean(xf, tc, coef)) * head(wc, mt)
                                      | jittered_cor(nd2_ff, eq_ff, head(beta_eta, p), nugget),
                                      wc[mt + 1] / lambda_eta, xf,
                                      beta_delta, lambda_delta, noise_weight / lambda_e, lapack);
  }
}
