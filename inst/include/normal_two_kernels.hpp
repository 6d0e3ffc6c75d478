// normal_two_kernels_lpdf(), declared in inst/stan/include/koh_functions.stan
// and defined here with its analytic gradient. It is the cost of every
// gradient of the grid and modular programs at large n, where Stan's
// reverse mode through an n x n Cholesky factor is several times slower
// than this analytic gradient (bench/results/gradient.md).
//
// This file is included by stan_meta_header.hpp inside each model's
// namespace, after the functions the Stan code defines and before the model
// class. The macro below points the class's calls at the definition here,
// so the definition does not have to repeat the exact template signature
// that stanc writes for the declaration (it differs between stanc2, used
// with rstan 2.21, and stanc3); the declaration itself is never called.

namespace bayesbem_cpp {

// Defined in src/lapack_inverse.cpp (R's headers cannot be included here).
extern "C" int bayesbem_lapack_inverse(int n, double* a, double* log_det);

// Adds x to the operands with the partial derivative g; data add nothing.
inline void add_operand(std::vector<stan::math::var>& ops, std::vector<double>& grads,
                        const stan::math::var& x, double g) {
  ops.push_back(x);
  grads.push_back(g);
}
inline void add_operand(std::vector<stan::math::var>&, std::vector<double>&, double,
                        double) {}

// g may be an expression: it is evaluated only for operands that are var.
template <int R, int C, typename G>
inline void add_operands(std::vector<stan::math::var>& ops, std::vector<double>& grads,
                         const Eigen::Matrix<stan::math::var, R, C>& x, const G& g) {
  const Eigen::MatrixXd gv = g;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    add_operand(ops, grads, x(i), gv(i));
  }
}
template <int R, int C, typename G>
inline void add_operands(std::vector<stan::math::var>&, std::vector<double>&,
                         const Eigen::Matrix<double, R, C>&, const G&) {}

// A block of a column-major matrix, for the recursions below.
typedef Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<> > MatrixBlock;

/* The lower triangle of a overwritten by its inverse, by halves (the
 * recursive TRTRI of ReLAPACK: Peise & Bientinesi 2017, ACM TOMS 44(2);
 * src/lapack_inverse.cpp does the same by BLAS calls):
 *   [L11 0; L21 L22]^-1 = [L11^-1 0; -L22^-1 L21 L11^-1  L22^-1],
 * so nearly all the flops are two triangular-by-full products per level. */
inline void invert_lower(MatrixBlock a) {
  const Eigen::Index n = a.rows();
  if (n <= 16) {
    Eigen::MatrixXd inv = Eigen::MatrixXd::Identity(n, n);
    a.triangularView<Eigen::Lower>().solveInPlace(inv);
    a.triangularView<Eigen::Lower>() = inv;
    return;
  }
  const Eigen::Index n1 = n / 2, n2 = n - n1;
  invert_lower(a.topLeftCorner(n1, n1));
  invert_lower(a.bottomRightCorner(n2, n2));
  const Eigen::MatrixXd l21 =
      a.bottomLeftCorner(n2, n1) * a.topLeftCorner(n1, n1).triangularView<Eigen::Lower>();
  a.bottomLeftCorner(n2, n1).noalias() =
      -(a.bottomRightCorner(n2, n2).triangularView<Eigen::Lower>() * l21);
}

/* The lower triangle of A' A for the lower triangular A in a, in place, by
 * halves (what LAPACK's dlauum does):
 *   A' A = [A11' A11 + A21' A21, (A22' A21)'; A22' A21, A22' A22]. */
inline void lower_cross_product(MatrixBlock a) {
  const Eigen::Index n = a.rows();
  if (n <= 16) {
    const Eigen::MatrixXd l = a.triangularView<Eigen::Lower>();
    a.triangularView<Eigen::Lower>() = l.transpose() * l;
    return;
  }
  const Eigen::Index n1 = n / 2, n2 = n - n1;
  lower_cross_product(a.topLeftCorner(n1, n1));
  a.topLeftCorner(n1, n1).selfadjointView<Eigen::Lower>().rankUpdate(
      a.bottomLeftCorner(n2, n1).transpose());
  const Eigen::MatrixXd a21 =
      a.bottomRightCorner(n2, n2).triangularView<Eigen::Lower>().transpose() *
      a.bottomLeftCorner(n2, n1);
  a.bottomLeftCorner(n2, n1) = a21;
  lower_cross_product(a.bottomRightCorner(n2, n2));
}

/* Factors Sigma once: returns log|Sigma|, sets alpha = Sigma^-1 r and
 * overwrites sigma with Sigma^-1: Sigma = L L', then L^-1 (invert_lower())
 * and Sigma^-1 = L^-T L^-1 (lower_cross_product()), n^3 flops in all, by
 * Eigen, or with `lapack` the same steps by R's LAPACK and BLAS (dpotrf,
 * dtrmm, dlauum: src/lapack_inverse.cpp), whichever is faster on the BLAS
 * R uses: R's use_lapack() (R/utils-lapack.R) chooses. */
inline double factor_sigma(Eigen::MatrixXd& sigma, const Eigen::VectorXd& r,
                           Eigen::VectorXd& alpha, bool lapack) {
  const char* not_pd = "normal_two_kernels_lpdf: the covariance is not positive definite";
  if (lapack) {
    double log_det = 0;
    if (bayesbem_lapack_inverse(static_cast<int>(sigma.rows()), sigma.data(), &log_det) != 0) {
      throw std::domain_error(not_pd);
    }
    sigma.triangularView<Eigen::StrictlyUpper>() = sigma.transpose();
    alpha = sigma * r;
    return log_det;
  }
  // factored in place: sigma's lower triangle becomes L
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd> > llt(sigma);
  if (llt.info() != Eigen::Success) {
    throw std::domain_error(not_pd);
  }
  alpha = llt.solve(r);
  const double log_det = 2 * sigma.diagonal().array().log().sum();
  invert_lower(sigma);
  lower_cross_product(sigma);
  sigma.triangularView<Eigen::StrictlyUpper>() = sigma.transpose();
  return log_det;
}

// The log density as a double, or as a var holding its partial derivatives.
inline double finish(double lp, const std::vector<stan::math::var>&,
                     const std::vector<double>&, double*) {
  return lp;
}
inline stan::math::var finish(double lp, const std::vector<stan::math::var>& ops,
                              const std::vector<double>& grads, stan::math::var*) {
  return stan::math::precomputed_gradients(lp, ops, grads);
}

/* The squared-exponential kernel
 *   S[i, j] = exp(-sum_k beta[k] (x[i, k] - x[j, k])^2) / lambda
 * (method Eq 2), lower triangle and diagonal only: S is symmetric, so half
 * the exponentials are half its cost. The squared distances are formed from
 * x as they are needed rather than read from an n^2 x (p + 1) table
 * (neg_sqdist()): timed alone at n = 365 the subtractions are the faster,
 * and the programs need not hold 4 MB of distances per chain. */
inline Eigen::MatrixXd sq_exp_lower(const Eigen::MatrixXd& x, const Eigen::VectorXd& beta,
                                    double lambda) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd S(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Index m = n - j;
    Eigen::ArrayXd log_s = Eigen::ArrayXd::Zero(m);
    for (Eigen::Index k = 0; k < beta.size(); ++k) {
      log_s -= beta(k) * (x.col(k).tail(m).array() - x(j, k)).square();
    }
    S.col(j).tail(m) = log_s.exp().matrix() / lambda;
  }
  return S;
}

/* The traces the gradient needs, tr(W M) = sum(W .* M) for symmetric M, from
 * the lower triangles of W = (alpha alpha' - Sigma^-1) / 2, K and S, each
 * off-diagonal entry counted twice: sum(W .* K), sum(W .* S), diag(W) and
 * d_beta[k] = -sum(W .* S .* D_k), D_k[i, j] = (x[i, k] - x[j, k])^2 (zero on
 * the diagonal). One pass, W never formed. */
struct Traces {
  double wk = 0, ws = 0;
  Eigen::VectorXd w, d_beta;
};
inline Traces lower_traces(const Eigen::VectorXd& alpha, const Eigen::MatrixXd& sigma_inv,
                           const Eigen::MatrixXd& K, const Eigen::MatrixXd& S,
                           const Eigen::MatrixXd& x) {
  const Eigen::Index n = alpha.size();
  Traces t;
  t.w = Eigen::VectorXd(n);
  t.d_beta = Eigen::VectorXd::Zero(x.cols());
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Index m = n - j;
    const Eigen::VectorXd w = 0.5 * (alpha(j) * alpha.tail(m) - sigma_inv.col(j).tail(m));
    const Eigen::ArrayXd ws = w.cwiseProduct(S.col(j).tail(m)).array();
    t.wk += 2 * w.dot(K.col(j).tail(m)) - w(0) * K(j, j);
    t.ws += 2 * ws.sum() - ws(0);
    t.w(j) = w(0);
    for (Eigen::Index k = 0; k < x.cols(); ++k) {
      t.d_beta(k) -= 2 * (ws * (x.col(k).tail(m).array() - x(j, k)).square()).sum();
    }
  }
  return t;
}

/* Log density of r ~ N(0, Sigma) with
 *   Sigma = a K + S + diag(d),  S the squared-exponential kernel of the rows
 * of x (sq_exp_lower()), d each row's noise variance. One Cholesky factor of Sigma gives the value,
 *   -0.5 (n log(2 pi) + log|Sigma| + r' alpha),  alpha = Sigma^-1 r,
 * and Sigma^-1 (factor_sigma(), by Eigen or by R's LAPACK as `lapack` says)
 * gives every partial derivative
 * (Rasmussen & Williams 2006, Eq 5.9): d/dtheta = tr(W dSigma/dtheta) with
 * W = (alpha alpha' - Sigma^-1) / 2,
 * so d/dr = -alpha, d/dK = a W, d/da = sum(W .* K), d/dbeta[k] =
 * -sum(W .* S .* D_k), d/dlambda = -sum(W .* S) / lambda, d/dd = diag(W)
 * (lower_traces()). */
template <typename TR, typename TK, typename TA, typename TX, typename TB, typename TL,
          typename TJ>
typename stan::return_type<TR, TK, TA, TB, TL, TJ>::type normal_two_kernels(
    const TR& r_in, const TK& K_in, const TA& a, const TX& x_in, const TB& beta_in,
    const TL& lambda, const TJ& d_in, bool lapack) {
  using stan::math::value_of;
  typedef typename stan::return_type<TR, TK, TA, TB, TL, TJ>::type result_t;
  // references: no copy when an argument already has the type (stanc2), a
  // temporary kept alive by the reference when it is an expression (stanc3)
  const Eigen::Matrix<typename TR::Scalar, Eigen::Dynamic, 1>& r = r_in;
  const Eigen::Matrix<typename TK::Scalar, Eigen::Dynamic, Eigen::Dynamic>& K = K_in;
  const Eigen::Matrix<typename TB::Scalar, Eigen::Dynamic, 1>& beta = beta_in;
  const Eigen::Matrix<typename TJ::Scalar, Eigen::Dynamic, 1>& d = d_in;
  const Eigen::MatrixXd& x = value_of(x_in);
  const Eigen::Index n = r.size();
  const Eigen::Index P = beta.size();
  stan::math::check_square("normal_two_kernels_lpdf", "K", K);
  stan::math::check_size_match("normal_two_kernels_lpdf", "rows of K", K.rows(), "size of r", n);
  stan::math::check_size_match("normal_two_kernels_lpdf", "rows of x", x.rows(), "size of r", n);
  stan::math::check_size_match("normal_two_kernels_lpdf", "columns of x", x.cols(),
                               "size of beta", P);
  stan::math::check_size_match("normal_two_kernels_lpdf", "size of d", d.size(), "size of r", n);
  const Eigen::VectorXd rv = value_of(r);
  const Eigen::MatrixXd& Kv = value_of(K);
  const double av = value_of(a);
  const double lambdav = value_of(lambda);
  const Eigen::MatrixXd S = sq_exp_lower(x, value_of(beta), lambdav);
  // the factor reads the lower triangle only; factor_sigma() then overwrites
  // sigma with the whole of Sigma^-1
  Eigen::MatrixXd sigma(n, n);
  sigma.triangularView<Eigen::Lower>() = av * Kv + S;
  sigma.diagonal() += value_of(d);
  Eigen::VectorXd alpha;
  const double log_det = factor_sigma(sigma, rv, alpha, lapack);
  const double lp = -0.5 * (n * std::log(2 * stan::math::pi()) + log_det + rv.dot(alpha));

  // sigma now holds Sigma^-1
  const Traces t = lower_traces(alpha, sigma, Kv, S, x);
  std::vector<stan::math::var> ops;
  std::vector<double> grads;
  add_operands(ops, grads, r, -alpha);
  add_operands(ops, grads, K, 0.5 * av * (alpha * alpha.transpose() - sigma));
  add_operand(ops, grads, a, t.wk);
  add_operands(ops, grads, beta, t.d_beta);
  add_operand(ops, grads, lambda, -t.ws / lambdav);
  add_operands(ops, grads, d, t.w);
  return finish(lp, ops, grads, static_cast<result_t*>(nullptr));
}

}  // namespace bayesbem_cpp

// The Stan programs call normal_two_kernels_lpdf<propto>(..., pstream__) or,
// under stanc2, without the template argument; both reach this definition.
template <bool propto = false, typename TR, typename TK, typename TA, typename TX,
          typename TB, typename TL, typename TJ>
typename stan::return_type<TR, TK, TA, TB, TL, TJ>::type bayesbem_normal_two_kernels_lpdf(
    const TR& r, const TK& K, const TA& a, const TX& x, const TB& beta, const TL& lambda,
    const TJ& d, const int& lapack, std::ostream* pstream__) {
  return bayesbem_cpp::normal_two_kernels(r, K, a, x, beta, lambda, d, lapack != 0);
}
#define normal_two_kernels_lpdf bayesbem_normal_two_kernels_lpdf
