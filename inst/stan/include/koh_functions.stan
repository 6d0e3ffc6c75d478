  /* Squared differences between the rows of u and v, one column per input
   * k: -(u[i, k] - v[j, k])^2 for every pair (i, j), stacked column-major
   * (i fastest), plus a last column of -1. Multiplied by (beta, log(lambda))
   * it gives the log of the squared-exponential covariance (method Eq 2), so
   * the data part is computed once and each covariance costs one
   * matrix-vector product. */
  matrix neg_sqdist(matrix u, matrix v) {
    int nu = rows(u);
    int nv = rows(v);
    int K = cols(u);
    matrix[nu * nv, K + 1] d;
    for (k in 1:K) {
      matrix[nu, nv] diff = rep_matrix(col(u, k), nv) - rep_matrix(col(v, k)', nu);
      d[, k] = -to_vector(diff .* diff);
    }
    d[, K + 1] = rep_vector(-1, nu * nv);
    return d;
  }

  /* (1 / lambda) * exp(-sum_k beta[k] * d2_k) as an nr x nc matrix, from
   * neg_sqdist() of the two sets of rows. */
  matrix sq_exp_cov(matrix neg_d2, vector beta, real lambda, int nr, int nc) {
    return to_matrix(exp(neg_d2 * append_row(beta, log(lambda))), nr, nc);
  }

  /* 1 where row i of u equals row j of v, else 0: the indicator the jitter
   * (nugget) of each kernel factor multiplies. */
  matrix equal_rows(matrix u, matrix v) {
    matrix[rows(u), rows(v)] eq;
    for (j in 1:rows(v)) {
      for (i in 1:rows(u)) {
        eq[i, j] = dot_self(u[i] - v[j]) == 0 ? 1 : 0;
      }
    }
    return eq;
  }

  /* One factor of the emulator kernel with its jitter: the correlation
   * exp(-sum_k beta[k] * d2_k) plus nugget where the rows are equal. The
   * jitter sits on the x and t factors separately, (k_x + a)(k_t + a) on the
   * diagonal, so that grid designs keep their Kronecker structure. */
  matrix jittered_cor(matrix neg_d2, matrix eq, vector beta, real nugget) {
    return sq_exp_cov(neg_d2, beta, 1, rows(eq), cols(eq)) + nugget * eq;
  }

  /* Correlations k_t(tf, t_a) between tf and each design row. */
  vector tf_cor(row_vector tf, matrix tc, vector beta_t) {
    matrix[rows(tc), cols(tc)] diff = rep_matrix(tf, rows(tc)) - tc;
    return exp(-(diff .* diff) * beta_t);
  }

  /* Sigma_z of z = (y, eta) for any design (method section 1): the product
   * kernel Sigma_eta over all rows, plus Sigma_delta + diag(noise) on the
   * field block, noise each field row's variance w_i / lambda_e. Field rows all sit at tf, so their t factor is 1 + nugget
   * between each other and one row vector k(tf, t_j) to the design rows. */
  matrix koh_cov(matrix nd2_ff, matrix nd2_fc, matrix nd2_cc, matrix nd2_tt,
                 matrix eq_ff, matrix eq_fc, matrix eq_cc, matrix eq_tt,
                 matrix tc, row_vector tf, vector beta_eta, vector beta_delta,
                 real lambda_eta, real lambda_delta, vector noise, real nugget) {
    int n = rows(eq_ff);
    int m = rows(tc);
    int p = rows(beta_delta);
    vector[p] beta_x = head(beta_eta, p);
    matrix[n, m] sigma_fc = jittered_cor(nd2_fc, eq_fc, beta_x, nugget)
                            .* rep_matrix(tf_cor(tf, tc, tail(beta_eta, cols(tc)))', n) / lambda_eta;
    matrix[n, n] sigma_ff = (1 + nugget) * jittered_cor(nd2_ff, eq_ff, beta_x, nugget) / lambda_eta
                            + sq_exp_cov(nd2_ff, beta_delta, lambda_delta, n, n);
    matrix[m, m] sigma_cc = jittered_cor(nd2_cc, eq_cc, beta_x, nugget)
                            .* jittered_cor(nd2_tt, eq_tt, tail(beta_eta, cols(tc)), nugget) / lambda_eta;
    return append_row(append_col(add_diag(sigma_ff, noise), sigma_fc),
                      append_col(sigma_fc', sigma_cc));
  }

  /* Log density of vec(E) ~ N(0, Kt (x) Kx / lambda_eta), the simulation
   * runs on a grid (E[i, a]: run a at grid input i), from the Cholesky
   * factors Lx and Lt of the jittered input and run correlations, without
   * forming the Kronecker product: log |Kt (x) Kx| = n_x log|Kt| + mt log|Kx|
   * and the quadratic form is the squared norm of Lx^-1 E Lt^-T. */
  real runs_grid_lpdf(matrix E, matrix Lx, matrix Lt, real lambda_eta) {
    int n_x = rows(E);
    int mt = cols(E);
    matrix[n_x, mt] white = mdivide_left_tri_low(Lt, mdivide_left_tri_low(Lx, E)')';
    return -0.5 * (n_x * mt * log(2 * pi()) - n_x * mt * log(lambda_eta)
                   + 2 * n_x * sum(log(diagonal(Lt))) + 2 * mt * sum(log(diagonal(Lx)))
                   + lambda_eta * sum(columns_dot_self(white)));
  }

  /* Log density of r ~ N(0, a K + S + diag(d)), d each row's noise
   * variance and S the squared-exponential kernel of the rows of x, sq_exp_cov(neg_sqdist(x, x), beta, lambda, n, n)
   * (method Eq 2). Defined in C++
   * with its analytic gradient (inst/include/normal_two_kernels.hpp): one
   * Cholesky factor and one inverse of the n x n covariance per gradient, by
   * R's LAPACK when lapack is 1, else by Eigen (R's use_lapack() chooses).
   * Only the model blocks call it (the C++ is visible there, not here). */
  real normal_two_kernels_lpdf(vector r, matrix K, real a, matrix x, vector beta, real lambda,
                               vector d, int lapack);

  /* Log density of r ~ N(0, B diag(v) B' + S + diag(d)), B the basis of a
   * principal-component emulator (data), v its components' variances at tf
   * and S the squared-exponential kernel of the rows of x, sq_exp_cov()
   * (the discrepancy): the field outputs given the runs under the basis
   * emulator (basis_components()). Defined in C++ with its analytic gradient
   * (inst/include/normal_basis.hpp), one Cholesky factor and one inverse of
   * the n x n covariance per gradient, as normal_two_kernels_lpdf(). */
  real normal_basis_lpdf(vector r, matrix B, vector v, matrix x, vector beta, real lambda,
                         vector d, int lapack);

  /* The components of a principal-component emulator at tf (Higdon,
   * Gattiker, Williams & Rightley 2008, JASA 103;
   * inst/notes/decisions/F4-the-basis-emulator-for-daily-data.md): component j
   * is a Gaussian process over the
   * parameters fitted to the runs' weights, so given them its mean is
   * h(tf)' b_j + k_j' alpha_j and its variance s2_j (1 + nug_j) -
   * k_j' Kj^-1 k_j, with h(tf) = (1, tf), k_j[a] = s2_j exp(-sum_k
   * beta[k, j] (tf[k] - tc[a, k])^2) and Kj^-1 rows (j - 1) mt + 1 to j mt
   * of Ki. Returns append_row(means, variances); a variance below zero by
   * rounding is taken as zero. */
  vector basis_components(vector tf, matrix tc, matrix coef, matrix beta, vector s2,
                          vector nug, matrix alpha, matrix Ki) {
    int mt = rows(tc);
    int pc = cols(coef);
    vector[2 * pc] out;
    for (j in 1:pc) {
      vector[mt] k;
      for (a in 1:mt) {
        k[a] = s2[j] * exp(-dot_product(col(beta, j), square(tf - tc[a]')));
      }
      out[j] = coef[1, j] + dot_product(tf, tail(col(coef, j), rows(tf)))
               + dot_product(k, col(alpha, j));
      out[pc + j] = fmax(s2[j] * (1 + nug[j])
                         - quad_form(block(Ki, (j - 1) * mt + 1, 1, mt, mt), k), 0);
    }
    return out;
  }

  /* The field outputs given the runs on a grid (inst/notes/decisions/S6-grid-designs.md):
   *   y | E ~ N((E w)[1:n], c Kx_ff / lambda_eta + Sigma_delta + diag(noise_weight) / lambda_e),
   * w = Kt^-1 k0 and c = 1 + nugget - k0' Kt^-1 k0, from the Cholesky factor
   * Lt of Kt and k0 = k_t(tf, t_a). Returns append_row(w, c). */
  vector runs_weights(matrix Lt, vector k0, real nugget) {
    vector[rows(Lt)] v = mdivide_left_tri_low(Lt, k0);
    return append_row(mdivide_right_tri_low(v', Lt)', 1 + nugget - dot_self(v));
  }

  /* The parametric discrepancy terms h * gamma at the field rows (zero when
   * there are none: rstan 2.21 refuses to multiply zero-size matrices). */
  vector discrepancy_terms(matrix h, vector gamma) {
    if (cols(h) == 0) {
      return rep_vector(0, rows(h));
    }
    return h * gamma;
  }

  /* Coefficients (intercept, x, t) of the emulator mean h(x, t)' b, b placed
   * in the columns of [1, x, t] that b_select picks and zero elsewhere
   * (rstan 2.21 refuses to multiply zero-size matrices). */
  vector mean_coefficients(matrix b_select, vector b) {
    if (cols(b_select) == 0) {
      return rep_vector(0, rows(b_select));
    }
    return b_select * b;
  }

  /* The emulator mean h(x, t)' b at rows (x[i], t[i]): coef[1] + x[i] * coef_x
   * + t[i] * coef_t. */
  vector emulator_mean(matrix x, matrix t, vector coef) {
    return coef[1] + x * segment(coef, 2, cols(x)) + t * tail(coef, cols(t));
  }

  /* The emulator mean on a grid: element (i, a) at grid input i and run a. */
  matrix grid_mean(matrix x_grid, matrix tc, vector coef) {
    return rep_matrix(coef[1] + x_grid * segment(coef, 2, cols(x_grid)), rows(tc))
           + rep_matrix((tc * tail(coef, cols(tc)))', rows(x_grid));
  }

  /* Log prior density of tf, each calibration parameter mapped to [0, 1]
   * by its design range on its scale (data-scales.R): s = lo + span * tf is
   * the parameter on that scale, v = s (identity, scale 0), exp(s) (log, 1)
   * or -1 / s (reciprocal, 2) in physical units, and w = (v - v_lo) / v_span
   * the physical value mapped to [0, 1] by the same range. The prior is
   * stated on w, as in the paper, whatever the scale: U(0, 1) where
   * is_normal[k] is 0, otherwise normal(mu[k], sd[k]) truncated to [0, 1];
   * so tf's density is the prior of w times |dw / dtf| = |dv / ds| span /
   * v_span (change of variables), with dv / ds = exp(s) or 1 / s^2. */
  real tf_prior_lpdf(vector tf, vector is_normal, vector mu, vector sd, vector scale,
                     vector lo, vector span, vector v_lo, vector v_span) {
    real lp = 0;
    for (k in 1:rows(tf)) {
      real s = lo[k] + span[k] * tf[k];
      real w = tf[k];
      if (scale[k] > 0.5) {
        if (scale[k] < 1.5) {
          w = (exp(s) - v_lo[k]) / v_span[k];
          lp = lp + s;
        } else {
          w = (-1 / s - v_lo[k]) / v_span[k];
          lp = lp - 2 * log(-s);
        }
        lp = lp + log(span[k]) - log(v_span[k]);
      }
      if (is_normal[k] > 0.5) {
        lp = lp + normal_lpdf(w | mu[k], sd[k])
             - log_diff_exp(normal_lcdf(1 | mu[k], sd[k]), normal_lcdf(0 | mu[k], sd[k]));
      }
    }
    return lp;
  }
