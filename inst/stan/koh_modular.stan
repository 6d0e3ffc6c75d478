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
// NUTS samples z, the parameters' unconstrained values u (Stan's own
// transforms: logit for tf and rho_delta, log for the precisions) whitened
// by a Laplace approximation N(u_loc, u_scale u_scale'), u = u_loc +
// u_scale * z (whiten_stage2() in R/fit-whitening.R). rstan cannot be given
// an initial mass matrix; in z the unit metric it starts from is already
// about right, so warm-up need not learn the posterior's scales and
// correlations. With u_loc = 0 and u_scale = I the program is the
// unwhitened one, and lp__ is the same at the same u in any whitening (the
// constant log |det u_scale| is left out).
functions {
#include /include/koh_functions.stan
}
data {
  int<lower=1> n;                        // field observations
  int<lower=1> mt;                       // simulation runs
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  vector[n] y;                           // field output
  matrix[n, p] xf;                       // field inputs
  matrix[mt, q] tc;                      // simulation design, one row per run
#include /include/koh_prior_data.stan
  // the stage-1 emulator
  vector[p + q] beta_eta_fixed;          // its correlation parameters
  real<lower=0> lambda_eta_fixed;        // its precision
  vector[n_b] b_fixed;                   // its mean coefficients
  matrix[n, mt] E_f;                     // runs at the field inputs less the emulator mean
  matrix[n, n] Kx_ff;                    // jittered correlation of the field inputs
  matrix[mt, mt] Lt;                     // Cholesky factor of the jittered run correlation
  // the whitening: u = u_loc + u_scale * z, u = (logit tf, logit rho_delta,
  // log lambda_delta, log lambda_e, gamma)
  vector[q + p + 2 + n_h] u_loc;
  matrix[q + p + 2 + n_h, q + p + 2 + n_h] u_scale;
}
transformed data {
  matrix[n * n, p + 1] nd2_ff = neg_sqdist(xf, xf);
  vector[1 + p + q] coef = mean_coefficients(b_select, b_fixed);
}
parameters {
  vector[q + p + 2 + n_h] z;             // the whitened unconstrained parameters
}
transformed parameters {
  vector[q + p + 2 + n_h] u = u_loc + u_scale * z;
  vector[q] tf = inv_logit(head(u, q));  // calibration parameters
  vector[p] rho_delta = inv_logit(segment(u, q + 1, p));
  real lambda_delta = exp(u[q + p + 1]); // precision of the discrepancy
  real lambda_e = exp(u[q + p + 2]);     // precision of the observation error
  vector[n_h] gamma = tail(u, n_h);      // coefficients of the discrepancy terms
  vector[p] beta_delta = -4 * log(rho_delta);
}
model {
  vector[mt + 1] wc = runs_weights(Lt, tf_cor(tf', tc, tail(beta_eta_fixed, q)), nugget);
  // log Jacobian of u -> (tf, rho_delta, lambda_delta, lambda_e), as Stan
  // adds it for <lower=0, upper=1> and <lower=0> declarations
  target += sum(log_inv_logit(head(u, q + p))) + sum(log1m_inv_logit(head(u, q + p)))
            + u[q + p + 1] + u[q + p + 2];
  target += beta_lpdf(rho_delta | rho_delta_a, rho_delta_b);
  target += gamma_lpdf(lambda_delta | lambda_delta_shape, lambda_delta_rate);
  target += gamma_lpdf(lambda_e | lambda_e_shape, lambda_e_rate);
  target += tf_prior_lpdf(tf | tf_is_normal, tf_mu, tf_sd, tf_scale, tf_lo, tf_span, tf_v_lo,
                            tf_v_span);
  target += normal_lpdf(gamma | 0, gamma_sd);
  target += normal_two_kernels_lpdf(y - emulator_mean(xf, rep_matrix(tf', n), coef)
                                    - discrepancy_terms(h, gamma) - E_f * head(wc, mt)
                                    | Kx_ff, wc[mt + 1] / lambda_eta_fixed, nd2_ff, beta_delta,
                                    lambda_delta, 1 / lambda_e);
}
generated quantities {
  // the fixed emulator, under the names of the joint programs
  vector[p + q] beta_eta = beta_eta_fixed;
  real lambda_eta = lambda_eta_fixed;
  vector[n_b] b = b_fixed;
}
