// Stage 2 of the modular KOH fit with a principal-component (basis)
// emulator (Higdon, Gattiker, Williams & Rightley 2008, JASA 103;
// inst/notes/decisions/F4-the-basis-emulator-for-daily-data.md): the
// calibration parameters, the
// discrepancy and the noise, given the runs at the field rows, whose
// centred outputs are B W' plus the truncated components (variance s2r per
// row), each column of W emulated over the parameters by its own Gaussian
// process fixed at stage 1 (R/fit-basis.R). Given the runs,
//   y - h' gamma ~ N(mu + B w(tf), B diag(v(tf)) B' + Sigma_delta + s2r I + diag(noise_weight) / lambda_e),
// each gradient one Cholesky factor and one inverse of an n x n matrix (C++,
// normal_basis_lpdf()). tf is sampled on a scale linear inside [0, 1]
// (linear_box_lp()), where the ridge a year of daily data leaves is
// straight, so that a dense metric fits it
// (inst/notes/decisions/F5-a-linear-scale-for-tf-in.md).
//
// Several outputs (meters) share tf; each has its own basis, components,
// discrepancy and noise, its rows and components a block of the stacked
// data, and the likelihood is the sum of the outputs' (as in koh.stan's
// stage 2). With one output this is the one-output model.
functions {
  // the GP kernels, the mean and discrepancy terms, the tf prior, the C++ densities
#include /include/koh_functions.stan
  // where each output's block of the stacked rows starts, its size, its discrepancy terms
#include /include/koh_outputs.stan
  /* The calibration parameters on [0, 1] from unconstrained u, linear
   * inside and with exponential tails within about a of the bounds:
   *   g(u) = a (log(1 + e^(u / a)) - log(1 + e^((u - 1) / a))),
   * g(u) ~ u on [a, 1 - a], a e^(u / a) below 0, 1 - a e^((1 - u) / a)
   * above 1; adds log g'(u) = log(inv_logit(u / a) - inv_logit((u - 1) / a))
   * to the target (change of variables). Used here in place of
   * Stan's logit: the ridge that a year of daily data leaves along the
   * parameters is straight on [0, 1] and bends on the logit scale
   * (inst/notes/decisions/F5-a-linear-scale-for-tf-in.md). */
  vector linear_box_lp(vector u, real a) {
    vector[rows(u)] tf;
    for (k in 1:rows(u)) {
      tf[k] = a * (log1p_exp(u[k] / a) - log1p_exp((u[k] - 1) / a));
      target += log_diff_exp(log_inv_logit(u[k] / a), log_inv_logit((u[k] - 1) / a));
    }
    return tf;
  }

  /* The Beta(a, b) prior of rho = inv_logit(x) with the change of variables
   * to x, summed over x's elements (the logistic-beta density):
   *   log Beta(rho | a, b) + log rho + log(1 - rho)
   *     = a log inv_logit(x) + b log(1 - inv_logit(x)) - log B(a, b),
   * computed from x: where the likelihood is flat in rho (an additive
   * discrepancy's length scale past its floor) x reaches 30 and more, where
   * 1 - rho computed from rho is lost to rounding and Beta's density at rho
   * diverges. With a = b = 1 it is the change of variables alone. */
  real logit_beta_lpdf(vector x, real a, real b) {
    real s = 0;
    for (k in 1:rows(x)) s += a * log_inv_logit(x[k]) + b * log1m_inv_logit(x[k]);
    return s - rows(x) * lbeta(a, b);
  }

  /* The log variance of each basis function's coefficient in the additive
   * Hilbert-space approximate discrepancy (R/gp-hsgp.R; Riutort-Mayol,
   * Burkner, Andersen, Solin & Vehtari 2023, Stat Comput 33, Eq 1):
   * input k's m functions, at frequencies omega, have the spectral density
   * of exp(-b d^2) / (p lambda), b = sqrt(beta[k]^2 + 0.08^2) (length
   * scales at most 2.5 input ranges, R's additive_beta()),
   *   (p lambda)^-1 sqrt(pi / b) exp(-omega^2 / (4 b)),
   * kept on the log scale: at the longest length scales it is below 1e-200. */
  vector hsgp_log_spectral(vector omega, vector beta, real lambda) {
    int m = rows(omega);
    int p = rows(beta);
    vector[m * p] s;
    for (k in 1:p) {
      real b = sqrt(square(beta[k]) + square(0.08));
      s[((k - 1) * m + 1):(k * m)] = 0.5 * log(pi() / b) - log(p * lambda) - square(omega) / (4 * b);
    }
    return s;
  }

  /* Log density of r ~ N(0, U diag(c) U' + d R), r of n_r elements, less
   * log|R| / 2 (the caller's), from rr = r'R^-1 r, ur = U'R^-1 r, uu_d =
   * U'R^-1 U / d and log c alone: with M = diag(1 / c) + uu_d (Woodbury's
   * identity and the determinant lemma; Rasmussen & Williams 2006, Eqs
   * A.9 and A.10), M = L L',
   *   r' Sigma^-1 r = (rr - v'v / d) / d, v = L^-1 ur,
   *   log|Sigma| = log|M| + sum(log c) + n_r log(d) + log|R|.
   * One Cholesky factor of a matrix of U's columns: no cost in the rows;
   * uu_d is the only matrix of parameters (its diagonal gets 1 / c). */
  real normal_lowrank(real rr, vector ur, matrix uu_d, vector log_c, real d, int n_r) {
    int r = rows(log_c);
    matrix[r, r] m = uu_d;
    matrix[r, r] L;
    vector[r] v;
    for (i in 1:r) m[i, i] += exp(-log_c[i]);
    L = cholesky_decompose(m);
    v = mdivide_left_tri_low(L, ur);
    return -0.5 * (n_r * log(2 * pi()) + 2 * sum(log(diagonal(L))) + sum(log_c) + n_r * log(d)
                   + (rr - dot_self(v) / d) / d);
  }

  /* Where output k's block of the Gram matrices starts (row and column):
   * its first component, after the m p + n_shift + 1 + n_h other columns of
   * each earlier output (R's hsgp_stan_data()). */
  int gram_start(vector pc_output, int k, int m, int p, int n_shift, int n_h) {
    return output_start(pc_output, k) + (k - 1) * (m * p + n_shift + 1 + n_h);
  }

  /* The log variance of each of output k's n_shift month shifts, 1 / lambda_shift[k]
   * (none without shifts). */
  vector shift_log_variance(vector lambda_shift, int k, int n_shift) {
    if (n_shift == 0) return rep_vector(0, 0);
    return rep_vector(-log(lambda_shift[k]), n_shift);
  }

  /* The cells of each output's U'U (U = [B_k, Phi_k, M_k]): (pc_k + m p + n_shift)^2 summed. */
  int lowrank_cells(vector pc_output, int K, int m, int p, int n_shift) {
    int cells = 0;
    for (k in 1:K) {
      int nu = output_size(pc_output, k) + m * p + n_shift;
      cells += nu * nu;
    }
    return cells;
  }
}
data {
  // n, mt, p, q, K; y, xf, tc, each row's output and noise weight
#include /include/koh_field_data.stan
  // the priors' parameters and the mean and discrepancy terms
#include /include/koh_prior_data.stan
  int<lower=0, upper=1> lapack;          // Sigma factored by R's LAPACK (1) or Eigen (0)
  // the scale of tf_u (R/fit-basis.R, linear_box)
  real<lower=0, upper=0.5> tf_edge;      // a, the width of g's tails
  real<lower=0> tf_multiplier;           // Stan samples tf_u / tf_multiplier
  // the basis emulators: output k's components are a block of columns
  int<lower=1> pc;                       // components, all outputs
  vector<lower=1, upper=K>[pc] pc_output; // the output of each component
  vector[n] mu_f;                        // the runs' mean at the field rows
  matrix[n, pc] B;                       // bases: output k's rows and components
  vector<lower=0>[K] s2r;                // variance of each output's truncated components
  matrix[q + 1, pc] w_coef;              // components' linear means
  matrix[q, pc] w_beta;                  // components' kernel weights
  vector<lower=0>[pc] w_s2;              // components' variances
  vector<lower=0>[pc] w_nug;             // components' nuggets
  matrix[mt, pc] w_alpha;                // Kj^-1 (w_j - H b_j)
  matrix[mt * pc, mt] w_Ki;              // Kj^-1, stacked
  // hsgp = 1: the discrepancy as an additive Hilbert-space approximate
  // Gaussian process (R/gp-hsgp.R), m basis functions per input at
  // frequencies omega; the likelihood then reads each output's Gram matrix
  // of Z_k = [B_k, Phi_k, M_k, y_k - mu_f_k, h_k] (block k of gram, from row
  // and column (first component of k) + (k - 1) (m p + n_shift + 1 + n_h)),
  // never the rows. M_k: with a shift per month (n_shift > 0), the rows'
  // indicators of the n_shift calendar months, each month's shift
  // N(0, 1 / lambda_shift[k]) a part of output k's noise (R/gp-noise.R)
  int<lower=0, upper=1> hsgp;
  int<lower=0> m;
  vector<lower=0>[m] omega;
  int<lower=0> n_shift;
  real<lower=0> lambda_shift_shape;
  real<lower=0> lambda_shift_rate;
  int<lower=0> n_z;                      // hsgp * (pc + K (m p + n_shift + 1 + n_h))
  matrix[n_z, n_z] gram;
  // ar = 1 (with hsgp): the truncated components and the noise AR(1) over
  // consecutive rows, coefficient phi[k] (R/gp-noise.R): gram_lag holds
  // Z_k' (S + S') Z_k, S the lag within segments of consecutive rows,
  // gram_end Z_k' E Z_k, E the segments' first and last rows (a one-row
  // segment's twice), n_seg each output's number of segments
  int<lower=0, upper=1> ar;
  matrix[ar * n_z, ar * n_z] gram_lag;
  matrix[ar * n_z, ar * n_z] gram_end;
  vector<lower=1>[ar * K] n_seg;
  // Stan samples z, u = u_offset + u_scale z (R/fit-chains.R, laplace_map():
  // the identity, or the Laplace approximation at a mode so that the
  // sampler's first, unit metric fits); u is the parameters' unconstrained
  // values in this order: tf_u / tf_multiplier (q), logit rho_delta (p K),
  // log lambda_delta (K), log lambda_e (K), gamma (n_h), logit((phi + 1) / 2) (ar K),
  // log lambda_shift (K if n_shift > 0)
  int<lower=1> n_u;
  vector[n_u] u_offset;
  matrix[n_u, n_u] u_scale;
}
transformed data {
  // with AR(1) noise, the columns vec(U_k'U_k), vec(U_k'E U_k) and
  // vec(U_k'(S + S')U_k) of each output k in turn (rows of the output's
  // cells, lowrank_cells()): U_k'R^-1 U_k is then one product of this data
  // with three scalars of phi, a single node of the autodiff graph
  int shifts = n_shift > 0;
  int cells = ar * lowrank_cells(pc_output, K, m, p, n_shift);
  matrix[cells, 3] gram_uu;
  {
    int at_cell = 0;
    for (k in 1:K * ar) {
      int nu = output_size(pc_output, k) + m * p + n_shift;
      int at = gram_start(pc_output, k, m, p, n_shift, n_h);
      gram_uu[(at_cell + 1):(at_cell + nu * nu), 1] = to_vector(block(gram, at, at, nu, nu));
      gram_uu[(at_cell + 1):(at_cell + nu * nu), 2] = to_vector(block(gram_end, at, at, nu, nu));
      gram_uu[(at_cell + 1):(at_cell + nu * nu), 3] = to_vector(block(gram_lag, at, at, nu, nu));
      at_cell += nu * nu;
    }
  }
}
parameters {
  vector[n_u] z;
}
transformed parameters {
  vector[n_u] u = u_offset + u_scale * z;
  // calibration parameters, tf = g(tf_u)
  vector[q] tf_u = tf_multiplier * head(u, q);
  // output k's rho_delta are elements (k - 1) p + 1 to k p
  vector[p * K] rho_delta = inv_logit(segment(u, q + 1, p * K));
  vector[K] lambda_delta = exp(segment(u, q + p * K + 1, K)); // each output's discrepancy precision
  vector[K] lambda_e = exp(segment(u, q + p * K + K + 1, K)); // each output's noise precision
  vector[n_h] gamma = head(tail(u, n_h + (ar + shifts) * K), n_h); // the discrepancy terms' coefficients
  vector[ar * K] phi = 2 * inv_logit(head(tail(u, (ar + shifts) * K), ar * K)) - 1; // AR(1)
  vector[shifts * K] lambda_shift = exp(tail(u, shifts * K)); // each output's month-shift precision
  vector[q] tf = linear_box_lp(tf_u, tf_edge);
  vector[p * K] beta_delta = -4 * log_inv_logit(segment(u, q + 1, p * K));
}
model {
  int at_cell = 0;  // the first row of output k's cells in gram_uu, less 1
  vector[2 * pc] wv = basis_components(tf, tc, w_coef, w_beta, w_s2, w_nug, w_alpha, w_Ki);
  // rho_delta's prior with its change of variables from u; the others' change
  // of variables from u ((phi + 1) / 2 ~ Beta(1, 1): phi uniform on (-1, 1))
  target += logit_beta_lpdf(segment(u, q + 1, p * K) | rho_delta_a, rho_delta_b)
            + sum(segment(u, q + p * K + 1, 2 * K))
            + logit_beta_lpdf(head(tail(u, (ar + shifts) * K), ar * K) | 1, 1)
            + sum(tail(u, shifts * K));
  // priors of the calibration parameters, the discrepancy's precision and the noise
#include /include/koh_stage2_priors.stan
  target += gamma_lpdf(lambda_shift | lambda_shift_shape, lambda_shift_rate);
  for (k in 1:K) {
    int s = output_start(output, k);
    int len = output_size(output, k);
    int c = output_start(pc_output, k);
    int pc_k = output_size(pc_output, k);
    if (hsgp) {
      // r = Z_k a, a = (-w, 0, 0, 1, -gamma), errors N(0, d R): r'R^-1 r = a' G a and
      // U'R^-1 r = (G a)[1:nu], G = Z_k' R^-1 Z_k; R = I, or with AR(1) errors
      // (1 - phi^2) R^-1 = (1 + phi^2) I - phi^2 E - phi (S + S') (tridiagonal
      // within segments) and log|R| = (rows - segments) log(1 - phi^2)
      int nu = pc_k + m * p + n_shift;
      int nz = nu + 1 + n_h;
      int at = gram_start(pc_output, k, m, p, n_shift, n_h);
      vector[nz] a = append_row(append_row(-segment(wv, c, pc_k), rep_vector(0, m * p + n_shift)),
                                append_row(rep_vector(1, 1), -gamma));
      vector[nu] log_c = append_row(append_row(log(segment(wv, pc + c, pc_k)),
                                               hsgp_log_spectral(omega, segment(beta_delta, (k - 1) * p + 1, p),
                                                                 lambda_delta[k])),
                                    shift_log_variance(lambda_shift, k, n_shift));
      real d_k = s2r[k] + noise_weight[s] / lambda_e[k];
      if (ar) {
        // G a from the data blocks times a; U'R^-1 U / d from gram_uu's columns
        real f2 = square(phi[k]);
        vector[3] weights = [1 + f2, -f2, -phi[k]]' / (1 - f2);
        vector[nz] ga = weights[1] * (block(gram, at, at, nz, nz) * a)
                        + weights[2] * (block(gram_end, at, at, nz, nz) * a)
                        + weights[3] * (block(gram_lag, at, at, nz, nz) * a);
        matrix[nu, nu] uu_d = to_matrix(block(gram_uu, at_cell + 1, 1, nu * nu, 3) * (weights / d_k),
                                        nu, nu);
        target += normal_lowrank(dot_product(a, ga), head(ga, nu), uu_d, log_c, d_k, len)
                  - 0.5 * (len - n_seg[k]) * log1m(f2);
        at_cell += nu * nu;
      } else {
        vector[nz] ga = block(gram, at, at, nz, nz) * a;
        target += normal_lowrank(dot_product(a, ga), head(ga, nu), block(gram, at, at, nu, nu) / d_k,
                                 log_c, d_k, len);
      }
    } else {
      target += normal_basis_lpdf(segment(y, s, len) - segment(mu_f, s, len)
                                - block(B, s, c, len, pc_k) * segment(wv, c, pc_k)
                                - output_terms(h, gamma, s, len)
                                | block(B, s, c, len, pc_k), segment(wv, pc + c, pc_k),
                                block(xf, s, 1, len, p), segment(beta_delta, (k - 1) * p + 1, p),
                                lambda_delta[k],
                                s2r[k] + segment(noise_weight, s, len) / lambda_e[k], lapack);
    }
  }
}
