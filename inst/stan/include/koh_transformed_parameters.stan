  // rho = exp(-beta / 4)
  vector[p + q] beta_eta = -4 * log(rho_eta);
  vector[p] beta_delta = -4 * log(rho_delta);
