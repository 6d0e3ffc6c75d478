  matrix[p + q, K] beta_eta_fixed;       // their correlation parameters
  vector<lower=0>[K] lambda_eta_fixed;   // their precisions
  matrix[n_b, K] b_fixed;                // their mean coefficients
