  vector<lower=0, upper=1>[q] tf;        // calibration parameters
  vector[p + q] log_beta_eta;            // log inverse squared length scales of the emulator
  vector[p] log_beta_delta;              // and of the discrepancy
  real<lower=0> lambda_eta;              // precision of the emulator
  real<lower=0> lambda_delta;            // precision of the discrepancy
  real<lower=0> lambda_e;                // precision of the observation error
  vector[n_h] gamma;                     // coefficients of the discrepancy terms
  vector[n_b] b;                         // coefficients of the emulator mean
