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

  /* Sigma_z of z = (y, eta) (method section 1): Sigma_eta over all rows,
   * plus Sigma_delta + I / lambda_e on the field block, plus a nugget on the
   * diagonal of Sigma_eta. Field rows all sit at tf, so the t part of their
   * distances to each other is zero and to the design rows is one row vector. */
  matrix koh_cov(int n, matrix nd2_ff, matrix nd2_fc, matrix nd2_cc, matrix tc, row_vector tf,
                 vector beta_eta, vector beta_delta,
                 real lambda_eta, real lambda_delta, real lambda_e, real nugget) {
    int p = rows(beta_delta);
    int q = cols(tc);
    int m = rows(tc);
    matrix[m, q] tf_minus_tc = rep_matrix(tf, m) - tc;
    row_vector[m] d2_tf = ((tf_minus_tc .* tf_minus_tc) * tail(beta_eta, q))';
    matrix[n, m] sigma_fc = exp(to_matrix(nd2_fc * append_row(head(beta_eta, p), log(lambda_eta)), n, m)
                                - rep_matrix(d2_tf, n));
    matrix[n, n] sigma_ff = sq_exp_cov(nd2_ff, head(beta_eta, p), lambda_eta, n, n)
                            + sq_exp_cov(nd2_ff, beta_delta, lambda_delta, n, n);
    matrix[m, m] sigma_cc = sq_exp_cov(nd2_cc, beta_eta, lambda_eta, m, m);
    return append_row(append_col(add_diag(sigma_ff, 1 / lambda_e + nugget), sigma_fc),
                      append_col(sigma_fc', add_diag(sigma_cc, nugget)));
  }

  /* Log prior of tf on [0, 1]: U(0, 1) where is_normal[k] is 0, otherwise
   * normal(mu[k], sd[k]) truncated to [0, 1] (the paper's informative levels). */
  real tf_prior_lpdf(vector tf, vector is_normal, vector mu, vector sd) {
    real lp = 0;
    for (k in 1:rows(tf)) {
      if (is_normal[k] > 0.5) {
        lp = lp + normal_lpdf(tf[k] | mu[k], sd[k])
             - log_diff_exp(normal_lcdf(1 | mu[k], sd[k]), normal_lcdf(0 | mu[k], sd[k]));
      }
    }
    return lp;
  }
