// The KOH model written the straightforward way, as in the paper's listing:
// the covariance is filled element by element with double loops. Same model,
// priors and nugget as inst/stan/koh.stan; used only as the benchmark baseline.
data {
  int<lower=1> n;
  int<lower=1> m;
  int<lower=1> p;
  int<lower=1> q;
  vector[n] y;
  vector[m] eta;
  matrix[n, p] xf;
  matrix[m, p] xc;
  matrix[m, q] tc;
  vector<lower=0, upper=1>[q] tf_is_normal;
  vector<lower=0, upper=1>[q] tf_mu;
  vector<lower=0>[q] tf_sd;
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
  real<lower=0> nugget;
}
transformed data {
  int N = n + m;
  vector[N] z = append_row(y, eta);
  vector[N] mu = rep_vector(0, N);
  matrix[N, p] x = append_row(xf, xc);
}
parameters {
  vector<lower=0, upper=1>[q] tf;
  vector<lower=0, upper=1>[p + q] rho_eta;
  vector<lower=0, upper=1>[p] rho_delta;
  real<lower=0> lambda_eta;
  real<lower=0> lambda_delta;
  real<lower=0> lambda_e;
}
transformed parameters {
  vector[p + q] beta_eta = -4 * log(rho_eta);
  vector[p] beta_delta = -4 * log(rho_delta);
}
model {
  matrix[N, p + q] xt;
  matrix[N, N] sigma_eta;
  matrix[n, n] sigma_delta;
  matrix[N, N] sigma_z;
  for (i in 1:n) {
    for (k in 1:p) xt[i, k] = x[i, k];
    for (k in 1:q) xt[i, p + k] = tf[k];
  }
  for (i in 1:m) {
    for (k in 1:p) xt[n + i, k] = x[n + i, k];
    for (k in 1:q) xt[n + i, p + k] = tc[i, k];
  }
  for (i in 1:N) {
    for (j in i:N) {
      real s = 0;
      for (k in 1:(p + q)) s = s + beta_eta[k] * pow(xt[i, k] - xt[j, k], 2);
      sigma_eta[i, j] = exp(-s) / lambda_eta;
      sigma_eta[j, i] = sigma_eta[i, j];
    }
    sigma_eta[i, i] = sigma_eta[i, i] + nugget;
  }
  for (i in 1:n) {
    for (j in i:n) {
      real s = 0;
      for (k in 1:p) s = s + beta_delta[k] * pow(xf[i, k] - xf[j, k], 2);
      sigma_delta[i, j] = exp(-s) / lambda_delta;
      sigma_delta[j, i] = sigma_delta[i, j];
    }
    sigma_delta[i, i] = sigma_delta[i, i] + 1 / lambda_e;
  }
  sigma_z = sigma_eta;
  sigma_z[1:n, 1:n] = sigma_eta[1:n, 1:n] + sigma_delta;
  target += beta_lpdf(rho_eta | rho_eta_a, rho_eta_b);
  target += beta_lpdf(rho_delta | rho_delta_a, rho_delta_b);
  target += gamma_lpdf(lambda_eta | lambda_eta_shape, lambda_eta_rate);
  target += gamma_lpdf(lambda_delta | lambda_delta_shape, lambda_delta_rate);
  target += gamma_lpdf(lambda_e | lambda_e_shape, lambda_e_rate);
  for (k in 1:q) {
    if (tf_is_normal[k] > 0.5) {
      target += normal_lpdf(tf[k] | tf_mu[k], tf_sd[k])
                - log_diff_exp(normal_lcdf(1 | tf_mu[k], tf_sd[k]), normal_lcdf(0 | tf_mu[k], tf_sd[k]));
    }
  }
  target += multi_normal_lpdf(z | mu, sigma_z);
}
