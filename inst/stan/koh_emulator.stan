// Stage 1 of the modular KOH fit (Liu, Bayarri & Berger 2009): the
// emulator's hyperparameters (correlation parameters, precision, mean
// coefficients) from the simulation runs alone, cutting the feedback from
// the field data. The runs form a grid: run a at grid input i in eta[i, a],
// so vec(eta - h' b) ~ N(0, Kt (x) Kx / lambda_eta), O(mt^3 + n_x^3) per
// gradient. koh_modular.stan then calibrates with the emulator fixed.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
}
data {
  int<lower=1> n;                        // field observations (sizes the prior data)
  int<lower=1> n_x;                      // grid inputs used
  int<lower=1> mt;                       // simulation runs
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  matrix[n_x, mt] eta;                   // simulator output of run a at grid input i
  matrix[n_x, p] x_grid;                 // grid inputs, shared by every run
  matrix[mt, q] tc;                      // simulation design, one row per run
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
}
transformed data {
  matrix[n_x * n_x, p + 1] nd2_xx = neg_sqdist(x_grid, x_grid);
  matrix[mt * mt, q + 1] nd2_tt = neg_sqdist(tc, tc);
  matrix[n_x, n_x] eq_xx = equal_rows(x_grid, x_grid);
  matrix[mt, mt] eq_tt = equal_rows(tc, tc);
}
parameters {
  vector<lower=0, upper=1>[p + q] rho_eta;
  real<lower=0> lambda_eta;              // precision of the emulator
  vector[n_b] b;                         // coefficients of the emulator mean
}
transformed parameters {
  // rho = exp(-beta / 4)
  vector[p + q] beta_eta = -4 * log(rho_eta);
}
model {
  matrix[n_x, n_x] Kx = jittered_cor(nd2_xx, eq_xx, head(beta_eta, p), nugget);
  matrix[mt, mt] Kt = jittered_cor(nd2_tt, eq_tt, tail(beta_eta, q), nugget);
  target += beta_lpdf(rho_eta | rho_eta_a, rho_eta_b);
  target += gamma_lpdf(lambda_eta | lambda_eta_shape, lambda_eta_rate);
  target += normal_lpdf(b | 0, b_sd);
  target += runs_grid_lpdf(eta - grid_mean(x_grid, tc, mean_coefficients(b_select, b))
                           | cholesky_decompose(Kx), cholesky_decompose(Kt), lambda_eta);
}
