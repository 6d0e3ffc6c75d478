  // output k's rho_delta are elements (k - 1) p + 1 to k p
  vector<lower=0, upper=1>[p * K] rho_delta;
  vector<lower=0>[K] lambda_delta;       // precision of each output's discrepancy
  vector<lower=0>[K] lambda_e;           // precision of each output's observation error
  vector[n_h] gamma;                     // coefficients of the discrepancy terms
