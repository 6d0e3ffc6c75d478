// Stage 2 of a modular calibration with a principal-component (basis)
// emulator, for bench/bench-basis-emulator.R (a prototype: no discrepancy,
// the paper's noise prior). The runs' outputs at the n field rows, centred
// by their mean over the runs, are E - mu = K W' + residual (SVD, pc
// components); each column of W is emulated over the parameters by its own
// Gaussian process (linear mean, squared-exponential kernel, hyperparameters
// fixed at stage 1). Given the runs, at tf (Higdon et al. 2008, JASA 103):
//   y - mu ~ N(K w(tf), K diag(v(tf)) K' + (s2r + 1 / lambda_e) I),
// w_j = h(tf)' b_j + k_j' alpha_j, v_j = s2_j (1 + nug_j) - k_j' Ki_j k_j,
// and by Woodbury in its stable form (M = I + V^1/2 K'K V^1/2 / s):
//   r' Sigma^-1 r = r'r / s - u' M^-1 u, u = V^1/2 K' r / s,
//   log|Sigma| = n log s + log|M|,
// so a gradient costs O(n pc + mt^2 pc), not an n x n factor.
data {
  int<lower=1> n;               // field rows
  int<lower=1> pc;              // components
  int<lower=1> q;               // calibration parameters
  int<lower=1> mt;              // runs
  vector[n] r0;                 // y - mu (scaled)
  matrix[n, pc] K;              // basis
  real<lower=0> s2r;            // variance of the truncated components, per row
  matrix[mt, q] tc;             // runs (scaled parameters)
  matrix[mt, pc] alpha;         // per component Kj^-1 (w - H bj)
  matrix[q + 1, pc] bcoef;      // per component linear mean
  matrix[q, pc] beta;           // per component kernel weights
  vector[pc] s2;                // per component variance
  vector[pc] nug;               // per component nugget (relative)
  matrix[mt * pc, mt] Ki;       // stacked Kj^-1
}
transformed data {
  matrix[pc, pc] KtK = crossprod(K);
}
parameters {
  vector<lower=0, upper=1>[q] tf;
  real<lower=0> lambda_e;
}
model {
  vector[pc] w;
  vector[pc] v;
  real s = s2r + 1 / lambda_e;
  vector[n] r;
  for (j in 1:pc) {
    vector[mt] k;
    for (a in 1:mt) k[a] = s2[j] * exp(-dot_product(col(beta, j), square(tf - tc[a]')));
    w[j] = bcoef[1, j] + dot_product(tf, segment(col(bcoef, j), 2, q)) + dot_product(k, col(alpha, j));
    v[j] = fmax(s2[j] * (1 + nug[j]) - quad_form(block(Ki, (j - 1) * mt + 1, 1, mt, mt), k), 0)
           + 1e-10;
  }
  r = r0 - K * w;
  {
    vector[pc] sv = sqrt(v);
    matrix[pc, pc] L = cholesky_decompose(add_diag(quad_form_diag(KtK, sv) / s, rep_vector(1, pc)));
    vector[pc] z = mdivide_left_tri_low(L, sv .* (K' * r) / s);
    target += -0.5 * (dot_self(r) / s - dot_self(z)) - 0.5 * (n * log(s) + 2 * sum(log(diagonal(L))));
  }
  target += gamma_lpdf(lambda_e | 10, 0.03);
}
