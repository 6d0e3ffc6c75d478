  // tf prior per parameter: 1 = truncated normal(tf_mu, tf_sd), 0 = U(0, 1)
  vector<lower=0, upper=1>[q] tf_is_normal;
  vector<lower=0, upper=1>[q] tf_mu;
  vector<lower=0>[q] tf_sd;
  // each parameter's scale (0 identity, 1 log, 2 reciprocal), its design
  // range on that scale (tf = (s - tf_lo) / tf_span) and in physical units
  vector<lower=0, upper=2>[q] tf_scale;
  vector[q] tf_lo;
  vector<lower=0>[q] tf_span;
  vector[q] tf_v_lo;
  vector<lower=0>[q] tf_v_span;
  // hyperpriors: rho ~ beta(a, b); lambda ~ gamma(shape, rate)
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
  real<lower=0> nugget;                  // jitter on each emulator kernel factor
  // parametric discrepancy terms h' gamma (Kennedy & O'Hagan's mean
  // functions), used by extend(): covariates at the field rows, scaled
  int<lower=0> n_h;
  matrix[n, n_h] h;
  real<lower=0> gamma_sd;                // prior sd of each gamma
  // emulator mean h(x, t)' b (Kennedy & O'Hagan 2001): b multiplies the n_b
  // columns of [1, x, t] that b_select picks (n_b = 0: the paper's zero mean)
  int<lower=0> n_b;
  matrix[1 + p + q, n_b] b_select;
  real<lower=0> b_sd;                    // prior sd of each b
