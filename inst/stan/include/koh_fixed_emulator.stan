  vector[p + q] beta_eta = beta_eta_fixed;
  real lambda_eta = lambda_eta_fixed;
  vector[n_b] b = b_fixed;
