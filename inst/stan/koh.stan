// Kennedy-O'Hagan calibration of a simulator (Chong & Menberg 2018, method.md
// section 1), for any simulation design. y and eta are standardised with
// eta's mean and sd; x and t are on [0, 1]. koh_grid.stan computes the same
// density faster when the runs form a grid over the field inputs.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
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
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  // inputs whose outputs are sampled as parameters (the paper's Appendix D);
  // n_pred = 0 leaves the model unchanged
  int<lower=0> n_pred;
  matrix[n_pred, p] x_pred;
  // each row's noise variance relative to 1 / lambda_e: observed, then predicted
  vector<lower=0>[n + n_pred] noise_weight;
}
transformed data {
  int n_all = n + n_pred;                // field block: observed rows, then predicted rows
  matrix[n_all, p] xf_all = append_row(xf, x_pred);
  vector[n_pred + m] zero = rep_vector(0, n_pred + m);
  // squared input differences and equal-row indicators, computed once
  matrix[n_all * n_all, p + 1] nd2_ff = neg_sqdist(xf_all, xf_all);
  matrix[n_all * m, p + 1] nd2_fc = neg_sqdist(xf_all, xc);
  matrix[m * m, p + 1] nd2_cc = neg_sqdist(xc, xc);
  matrix[m * m, q + 1] nd2_tt = neg_sqdist(tc, tc);
  matrix[n_all, n_all] eq_ff = equal_rows(xf_all, xf_all);
  matrix[n_all, m] eq_fc = equal_rows(xf_all, xc);
  matrix[m, m] eq_cc = equal_rows(xc, xc);
  matrix[m, m] eq_tt = equal_rows(tc, tc);
}
parameters {
  // tf, rho_eta, rho_delta, lambda_eta, lambda_delta, lambda_e, gamma, b
#include /include/koh_parameters.stan
  vector[n_pred] y_pred;                 // field outputs at x_pred, noise included
}
transformed parameters {
  // beta_eta and beta_delta, the correlation parameters on the log scale
#include /include/koh_transformed_parameters.stan
}
model {
  vector[n_all + m] z = append_row(append_row(y, y_pred), eta);
  vector[1 + p + q] coef = mean_coefficients(b_select, b);
  // emulator mean h(x, t)' b of every row (field rows at tf), plus the
  // discrepancy terms on the observed field rows
  vector[n_all + m] mu = append_row(emulator_mean(xf_all, rep_matrix(tf', n_all), coef),
                                    emulator_mean(xc, tc, coef))
                         + append_row(discrepancy_terms(h, gamma), zero);
  matrix[n_all + m, n_all + m] sigma_z = koh_cov(nd2_ff, nd2_fc, nd2_cc, nd2_tt,
                                                 eq_ff, eq_fc, eq_cc, eq_tt, tc, tf',
                                                 beta_eta, beta_delta, lambda_eta,
                                                 lambda_delta, noise_weight / lambda_e, nugget);
  // the priors of every parameter
#include /include/koh_priors.stan
  target += multi_normal_cholesky_lpdf(z | mu, cholesky_decompose(sigma_z));
}
