// Kennedy-O'Hagan calibration of a simulator (Chong & Menberg 2018, method.md
// section 1) and its modular fit (Liu, Bayarri & Berger 2009), one program
// for four likelihoods chosen by the data `likelihood`; y and the runs are
// standardised with the runs' mean and sd, x and t are on [0, 1].
//   1 dense: the joint density of (y, eta) for any simulation design,
//     O((n + m)^3) per gradient.
//   2 grid: the same density when every run is made at the field inputs
//     (inst/notes/decisions/S6-grid-designs.md): the runs' Kronecker density
//     times the field outputs' density given the runs, O(mt^3 + n^3).
//   3 stage 1 of the modular fit: the emulator's hyperparameters from the
//     runs on the grid alone, cutting the feedback from the field data.
//   4 stage 2: the calibration parameters, the discrepancy and the noise of
//     each of K outputs (meters) with the emulators fixed at stage 1; given
//     tf the outputs are independent, so the likelihood is the sum of each
//     output's, each one Cholesky factor of its rows in C++.
// A parameter the likelihood does not sample has no elements. The
// principal-component emulator's stage 2 is koh_basis.stan.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
  // where each output's block of the stacked rows starts, its size, its discrepancy terms
#include /include/koh_outputs.stan
}
data {
  int<lower=1, upper=4> likelihood;      // 1 dense, 2 grid, 3 stage 1, 4 stage 2
  // n, mt, p, q, K; y, xf, tc, each row's output and noise weight
#include /include/koh_field_data.stan
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  int<lower=0, upper=1> lapack;          // Sigma factored by R's LAPACK (1) or Eigen (0)
  // dense: the simulation rows' inputs and outputs (tc's rows), and inputs
  // whose outputs are sampled as parameters (the paper's Appendix D)
  matrix[(likelihood == 1) * mt, p] xc;
  vector[(likelihood == 1) * mt] eta_c;
  int<lower=0> n_pred;
  matrix[n_pred, p] x_pred;
  vector<lower=0>[n_pred] noise_weight_pred;
  // grid and stage 1: run a at grid input i in eta[i, a]
  int<lower=0> n_x;
  matrix[n_x, mt] eta;
  matrix[n_x, p] x_grid;
  // grid: the runs at each field row's grid input
  matrix[(likelihood == 2) * n, mt] eta_f;
  // stage 2: each output's emulator, one column each (correlation
  // parameters, precision, mean coefficients); the runs at the field inputs
  // less the emulator mean, the field block of each output's Kx (n_max
  // columns, the largest output's rows) and the Cholesky factor of its Kt
  matrix[p + q, (likelihood == 4) * K] beta_eta_fixed;
  vector<lower=0>[(likelihood == 4) * K] lambda_eta_fixed;
  matrix[n_b, (likelihood == 4) * K] b_fixed;
  int<lower=0> n_max;
  matrix[(likelihood == 4) * n, mt] E_f;
  matrix[(likelihood == 4) * n, n_max] Kx_ff;
  matrix[(likelihood == 4) * K * mt, mt] Lt;
}
transformed data {
  int dense = likelihood == 1;
  int joint = likelihood <= 2;
  int stage1 = likelihood == 3;
  int stage2 = likelihood == 4;
  int n_all = n + n_pred;                // field block: observed rows, then predicted rows
  matrix[n_all, p] xf_all = append_row(xf, x_pred);
  vector[n_all] noise_all = append_row(noise_weight, noise_weight_pred);
  // squared input differences and equal-row indicators, computed once, each
  // for the likelihoods that read it (none for stage 2: its Kx and Kt are data)
  matrix[joint * n_all * n_all, p + 1] nd2_ff;
  matrix[joint * n_all, joint * n_all] eq_ff;
  matrix[dense * n_all * mt, p + 1] nd2_fc;
  matrix[dense * n_all, dense * mt] eq_fc;
  matrix[dense * mt * mt, p + 1] nd2_cc;
  matrix[dense * mt, dense * mt] eq_cc;
  matrix[n_x * n_x, p + 1] nd2_xx;
  matrix[n_x, n_x] eq_xx;
  matrix[(1 - stage2) * mt * mt, q + 1] nd2_tt;
  matrix[(1 - stage2) * mt, (1 - stage2) * mt] eq_tt;
  matrix[1 + p + q, stage2 * K] coef_fixed;
  if (joint) {
    nd2_ff = neg_sqdist(xf_all, xf_all);
    eq_ff = equal_rows(xf_all, xf_all);
  }
  if (dense) {
    nd2_fc = neg_sqdist(xf_all, xc);
    eq_fc = equal_rows(xf_all, xc);
    nd2_cc = neg_sqdist(xc, xc);
    eq_cc = equal_rows(xc, xc);
  }
  if (n_x > 0) {
    nd2_xx = neg_sqdist(x_grid, x_grid);
    eq_xx = equal_rows(x_grid, x_grid);
  }
  if (stage2) {
    for (k in 1:K) {
      coef_fixed[, k] = mean_coefficients(b_select, col(b_fixed, k));
    }
  } else {
    nd2_tt = neg_sqdist(tc, tc);
    eq_tt = equal_rows(tc, tc);
  }
}
parameters {
  vector<lower=0, upper=1>[(1 - stage1) * q] tf;          // calibration parameters
  vector<lower=0, upper=1>[(1 - stage2) * (p + q)] rho_eta;
  // output k's rho_delta are elements (k - 1) p + 1 to k p
  vector<lower=0, upper=1>[(1 - stage1) * p * K] rho_delta;
  vector<lower=0>[1 - stage2] lambda_eta;                 // precision of the emulator
  vector<lower=0>[(1 - stage1) * K] lambda_delta;         // precision of each output's discrepancy
  vector<lower=0>[(1 - stage1) * K] lambda_e;             // precision of each output's noise
  vector[(1 - stage1) * n_h] gamma;                       // coefficients of the discrepancy terms
  vector[(1 - stage2) * n_b] b;                           // coefficients of the emulator mean
  vector[n_pred] y_pred;                 // field outputs at x_pred, noise included
}
transformed parameters {
  // rho = exp(-beta / 4)
  vector[(1 - stage2) * (p + q)] beta_eta = -4 * log(rho_eta);
  vector[(1 - stage1) * p * K] beta_delta = -4 * log(rho_delta);
}
model {
  target += beta_lpdf(rho_eta | rho_eta_a, rho_eta_b);
  target += beta_lpdf(rho_delta | rho_delta_a, rho_delta_b);
  target += gamma_lpdf(lambda_eta | lambda_eta_shape, lambda_eta_rate);
  target += gamma_lpdf(lambda_delta | lambda_delta_shape, lambda_delta_rate);
  target += gamma_lpdf(lambda_e | lambda_e_shape, lambda_e_rate);
  target += tf_prior_lpdf(tf | tf_is_normal, tf_mu, tf_sd, tf_scale, tf_lo, tf_span, tf_v_lo,
                            tf_v_span);
  target += normal_lpdf(gamma | 0, gamma_sd);
  target += normal_lpdf(b | 0, b_sd);
  if (dense) {
    vector[n_all + mt] z = append_row(append_row(y, y_pred), eta_c);
    vector[1 + p + q] coef = mean_coefficients(b_select, b);
    // emulator mean h(x, t)' b of every row (field rows at tf), plus the
    // discrepancy terms on the observed field rows
    vector[n_all + mt] mu = append_row(emulator_mean(xf_all, rep_matrix(tf', n_all), coef),
                                       emulator_mean(xc, tc, coef))
                            + append_row(discrepancy_terms(h, gamma), rep_vector(0, n_pred + mt));
    matrix[n_all + mt, n_all + mt] sigma_z = koh_cov(nd2_ff, nd2_fc, nd2_cc, nd2_tt,
                                                     eq_ff, eq_fc, eq_cc, eq_tt, tc, tf',
                                                     beta_eta, beta_delta, lambda_eta[1],
                                                     lambda_delta[1], noise_all / lambda_e[1],
                                                     nugget);
    target += multi_normal_cholesky_lpdf(z | mu, cholesky_decompose(sigma_z));
  } else if (joint || stage1) {
    // the runs' Kronecker density: what the emulator mean leaves of the runs
    // is N(0, Kt (x) Kx / lambda_eta)
    vector[1 + p + q] coef = mean_coefficients(b_select, b);
    matrix[mt, mt] Lt_eta = cholesky_decompose(jittered_cor(nd2_tt, eq_tt, tail(beta_eta, q),
                                                            nugget));
    target += runs_grid_lpdf(eta - grid_mean(x_grid, tc, coef)
                             | cholesky_decompose(jittered_cor(nd2_xx, eq_xx, head(beta_eta, p),
                                                               nugget)),
                             Lt_eta, lambda_eta[1]);
    if (joint) {
      // times the field outputs' density given the runs (runs_weights())
      vector[mt + 1] wc = runs_weights(Lt_eta, tf_cor(tf', tc, tail(beta_eta, q)), nugget);
      target += normal_two_kernels_lpdf(y - emulator_mean(xf, rep_matrix(tf', n), coef)
                                        - discrepancy_terms(h, gamma)
                                        - (eta_f - grid_mean(xf, tc, coef)) * head(wc, mt)
                                        | jittered_cor(nd2_ff, eq_ff, head(beta_eta, p), nugget),
                                        wc[mt + 1] / lambda_eta[1], xf,
                                        beta_delta, lambda_delta[1], noise_weight / lambda_e[1],
                                        lapack);
    }
  } else {
    for (k in 1:K) {
      int s = output_start(output, k);
      int len = output_size(output, k);
      vector[mt + 1] wc = runs_weights(block(Lt, (k - 1) * mt + 1, 1, mt, mt),
                                       tf_cor(tf', tc, tail(col(beta_eta_fixed, k), q)), nugget);
      target += normal_two_kernels_lpdf(segment(y, s, len)
                                        - emulator_mean(block(xf, s, 1, len, p),
                                                        rep_matrix(tf', len), col(coef_fixed, k))
                                        - output_terms(h, gamma, s, len)
                                        - block(E_f, s, 1, len, mt) * head(wc, mt)
                                        | block(Kx_ff, s, 1, len, len),
                                        wc[mt + 1] / lambda_eta_fixed[k], block(xf, s, 1, len, p),
                                        segment(beta_delta, (k - 1) * p + 1, p), lambda_delta[k],
                                        segment(noise_weight, s, len) / lambda_e[k], lapack);
    }
  }
}
