// Kennedy-O'Hagan calibration of a simulator (Chong & Menberg 2018, method.md
// section 1). y and eta are standardised with eta's mean and sd; x and t are on [0, 1].
functions {
#include /include/koh_functions.stan
}
data {
  int<lower=1> n;                        // field observations
  int<lower=1> m;                        // simulation rows
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  vector[n] y;                           // field output
  vector[m] eta;                         // simulator output
  matrix[n, p] xf;                       // field inputs
  matrix[m, p] xc;                       // simulation inputs
  matrix[m, q] tc;                       // simulation design
  // tf prior per parameter: 1 = truncated normal(tf_mu, tf_sd), 0 = U(0, 1)
  vector<lower=0, upper=1>[q] tf_is_normal;
  vector<lower=0, upper=1>[q] tf_mu;
  vector<lower=0>[q] tf_sd;
  // hyperpriors: rho ~ beta(a, b); lambda ~ gamma(shape, rate)
  real<lower=0> rho_eta_a;
  real<lower=0> rho_eta_b;
  real<lower=0> rho_delta_a;
  real<lower=0> rho_delta_b;
  real<lower=0> lambda_eta_shape;
  real<lower=0> lambda_eta_rate;
  real<lower=0> lambda_delta_shape;
  real<lower=0> lambda_delta_rate;
  real<lower=0> lambda_e_shape;
  real<lower=0> lambda_e_rate;
  real<lower=0> nugget;                  // added to Sigma_eta's diagonal
  // inputs whose outputs are sampled as parameters (the paper's Appendix D);
  // n_pred = 0 leaves the model unchanged
  int<lower=0> n_pred;
  matrix[n_pred, p] x_pred;
}
transformed data {
  int n_all = n + n_pred;                // field block: observed rows, then predicted rows
  matrix[n_all, p] xf_all = append_row(xf, x_pred);
  vector[n_all + m] zero = rep_vector(0, n_all + m);
  // squared input differences, computed once (see neg_sqdist)
  matrix[n_all * n_all, p + 1] nd2_ff = neg_sqdist(xf_all, xf_all);
  matrix[n_all * m, p + 1] nd2_fc = neg_sqdist(xf_all, xc);
  matrix[m * m, p + q + 1] nd2_cc = neg_sqdist(append_col(xc, tc), append_col(xc, tc));
}
parameters {
  vector<lower=0, upper=1>[q] tf;        // calibration parameters
  vector<lower=0, upper=1>[p + q] rho_eta;
  vector<lower=0, upper=1>[p] rho_delta;
  real<lower=0> lambda_eta;              // precision of the emulator
  real<lower=0> lambda_delta;            // precision of the discrepancy
  real<lower=0> lambda_e;                // precision of the observation error
  vector[n_pred] y_pred;                 // field outputs at x_pred, noise included
}
transformed parameters {
  // rho = exp(-beta / 4)
  vector[p + q] beta_eta = -4 * log(rho_eta);
  vector[p] beta_delta = -4 * log(rho_delta);
}
model {
  vector[n_all + m] z = append_row(append_row(y, y_pred), eta);
  matrix[n_all + m, n_all + m] sigma_z = koh_cov(n_all, nd2_ff, nd2_fc, nd2_cc, tc, tf', beta_eta, beta_delta,
                                         lambda_eta, lambda_delta, lambda_e, nugget);
  target += beta_lpdf(rho_eta | rho_eta_a, rho_eta_b);
  target += beta_lpdf(rho_delta | rho_delta_a, rho_delta_b);
  target += gamma_lpdf(lambda_eta | lambda_eta_shape, lambda_eta_rate);
  target += gamma_lpdf(lambda_delta | lambda_delta_shape, lambda_delta_rate);
  target += gamma_lpdf(lambda_e | lambda_e_shape, lambda_e_rate);
  target += tf_prior_lpdf(tf | tf_is_normal, tf_mu, tf_sd);
  target += multi_normal_cholesky_lpdf(z | zero, cholesky_decompose(sigma_z));
}
