// normal_basis_lpdf(), declared in inst/stan/include/koh_functions.stan and
// defined here with its analytic gradient, for koh_basis.stan: the field
// outputs given the runs under a principal-component (basis) emulator.
// Included by stan_meta_header.hpp after normal_two_kernels.hpp, whose
// helpers (factor_sigma(), sq_exp_lower(), lower_traces(), the operands)
// it uses; the macro at the end points the Stan programs' calls here, as
// normal_two_kernels.hpp explains.

namespace bayesbem_cpp {

/* Log density of r ~ N(0, Sigma) with
 *   Sigma = B diag(v) B' + S + diag(d),
 * B the basis (data), v the components' variances, S the squared-
 * exponential kernel of the rows of x (the discrepancy). As
 * normal_two_kernels() with a K = B diag(v) B' that is data, plus the
 * partial derivatives in v (Rasmussen & Williams 2006, Eq 5.9, with
 * dSigma/dv_j = b_j b_j'):
 *   d/dv_j = b_j' W b_j = ((b_j' alpha)^2 - b_j' Sigma^-1 b_j) / 2,
 * W = (alpha alpha' - Sigma^-1) / 2, alpha = Sigma^-1 r. */
template <typename TR, typename TV, typename TX, typename TB, typename TL, typename TJ>
typename stan::return_type<TR, TV, TB, TL, TJ>::type normal_basis(
    const TR& r_in, const Eigen::MatrixXd& B, const TV& v_in, const TX& x_in,
    const TB& beta_in, const TL& lambda, const TJ& d_in, bool lapack) {
  using stan::math::value_of;
  typedef typename stan::return_type<TR, TV, TB, TL, TJ>::type result_t;
  const Eigen::Matrix<typename TR::Scalar, Eigen::Dynamic, 1>& r = r_in;
  const Eigen::Matrix<typename TV::Scalar, Eigen::Dynamic, 1>& v = v_in;
  const Eigen::Matrix<typename TB::Scalar, Eigen::Dynamic, 1>& beta = beta_in;
  const Eigen::Matrix<typename TJ::Scalar, Eigen::Dynamic, 1>& d = d_in;
  const Eigen::MatrixXd& x = value_of(x_in);
  const Eigen::Index n = r.size();
  stan::math::check_size_match("normal_basis_lpdf", "rows of B", B.rows(), "size of r", n);
  stan::math::check_size_match("normal_basis_lpdf", "columns of B", B.cols(), "size of v",
                               v.size());
  stan::math::check_size_match("normal_basis_lpdf", "rows of x", x.rows(), "size of r", n);
  stan::math::check_size_match("normal_basis_lpdf", "columns of x", x.cols(), "size of beta",
                               beta.size());
  stan::math::check_size_match("normal_basis_lpdf", "size of d", d.size(), "size of r", n);
  const Eigen::VectorXd rv = value_of(r);
  const Eigen::VectorXd vv = value_of(v);
  const double lambdav = value_of(lambda);
  const Eigen::MatrixXd K = B * vv.asDiagonal() * B.transpose();
  const Eigen::MatrixXd S = sq_exp_lower(x, value_of(beta), lambdav);
  Eigen::MatrixXd sigma(n, n);
  sigma.triangularView<Eigen::Lower>() = K + S;
  sigma.diagonal() += value_of(d);
  Eigen::VectorXd alpha;
  const double log_det = factor_sigma(sigma, rv, alpha, lapack);
  const double lp = -0.5 * (n * std::log(2 * stan::math::pi()) + log_det + rv.dot(alpha));

  // sigma now holds Sigma^-1
  const Traces t = lower_traces(alpha, sigma, K, S, x);
  const Eigen::VectorXd ba = B.transpose() * alpha;
  // diag(B' Sigma^-1 B), n^2 pc flops
  const Eigen::VectorXd quad = (B.transpose() * sigma).cwiseProduct(B.transpose()).rowwise().sum();
  const Eigen::VectorXd d_v = 0.5 * (ba.array().square() - quad.array()).matrix();
  std::vector<stan::math::var> ops;
  std::vector<double> grads;
  add_operands(ops, grads, r, -alpha);
  add_operands(ops, grads, v, d_v);
  add_operands(ops, grads, beta, t.d_beta);
  add_operand(ops, grads, lambda, -t.ws / lambdav);
  add_operands(ops, grads, d, t.w);
  return finish(lp, ops, grads, static_cast<result_t*>(nullptr));
}

}  // namespace bayesbem_cpp

template <bool propto = false, typename TR, typename TB_, typename TV, typename TX, typename TB,
          typename TL, typename TJ>
typename stan::return_type<TR, TV, TB, TL, TJ>::type bayesbem_normal_basis_lpdf(
    const TR& r, const TB_& B, const TV& v, const TX& x, const TB& beta, const TL& lambda,
    const TJ& d, const int& lapack, std::ostream* pstream__) {
  return bayesbem_cpp::normal_basis(r, stan::math::value_of(B), v, x, beta, lambda, d,
                                    lapack != 0);
}
#define normal_basis_lpdf bayesbem_normal_basis_lpdf
