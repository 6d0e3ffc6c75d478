  vector<lower=0, upper=1>[p] rho_delta;
  real<lower=0> lambda_delta;            // precision of the discrepancy
  real<lower=0> lambda_e;                // precision of the observation error
  vector[n_h] gamma;                     // coefficients of the discrepancy terms
