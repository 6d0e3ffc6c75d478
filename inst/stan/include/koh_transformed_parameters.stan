  // rho = exp(-beta / 4)
  vector[p + q] beta_eta = exp(log_beta_eta);
  vector[p] beta_delta = exp(log_beta_delta);
