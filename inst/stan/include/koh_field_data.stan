  int<lower=1> n;                        // field observations, all outputs
  int<lower=1> mt;                       // simulation runs (dense likelihood: simulation rows)
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  vector[n] y;                           // field outputs, each standardised on its own
  matrix[n, p] xf;                       // field inputs, on each output's own scaling
  matrix[mt, q] tc;                      // simulation design, one row per run
  int<lower=1> K;                        // outputs (meters)
  // the output of each field row, 1 to K: output 1's rows first, then 2's
  vector<lower=1, upper=K>[n] output;
  vector<lower=0>[n] noise_weight;       // each field row's noise variance relative to 1 / lambda_e
