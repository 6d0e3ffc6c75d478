  vector[(p + q) * K] beta_eta = to_vector(beta_eta_fixed);
  vector[K] lambda_eta = lambda_eta_fixed;
  vector[n_b * K] b = to_vector(b_fixed);
