// The posterior of one GP output, ready to predict (paper eq. 5 and Algorithm 1): everything
// that does not depend on the test input is computed once, so the mean at a new input costs one
// kernel row times a stored weight vector, O(n) (exact) or O(M) (sparse).
//
//   exact:  mean = k_*^T alpha,  alpha = (K + S)^-1 (y - mu_bar);  var = k_** - |L^-1 k_*|^2
//   sparse (VFE / DTC predictive, inducing inputs Z):
//           mean = k_*Z^T w,  w = (K_ZZ + K_Zn S^-1 K_nZ)^-1 K_Zn S^-1 (y - mu_bar)
//           var = k_** - k_*Z^T V k_*Z,  V = K_ZZ^-1 - (K_ZZ + K_Zn S^-1 K_nZ)^-1
// An exact posterior on more than kGpLowRankVarianceInputs inputs predicts its variance in
// O(M^2) instead of O(n^2): k_* is projected on M = kGpVarianceInducingInputs inducing inputs
// (k_* ~ K_nZ K_ZZ^-1 k_*Z), so that |L^-1 k_*|^2 ~ k_*Z^T V_e k_*Z with the cached
// V_e = K_ZZ^-1 K_Zn (K + S)^-1 K_nZ K_ZZ^-1: one fast path at every size above M (the O(n^2)
// solve cost a 900-input model ~500 us per prediction), k_*Z^T V_e k_*Z read from V_e's lower
// triangle. Above M inputs the mean is
// projected the same way, k_*^T alpha ~ k_*Z^T w_Z with w_Z = K_ZZ^-1 K_Zn alpha (O(M), the
// k_*Z of the variance), but only if that agrees with the exact mean within 1 % of the smallest
// noise sigma on (up to 256 of) the training inputs; otherwise the mean stays exact, O(n)
// (the exact O(n) mean is most of a 900-input model's prediction time).
// The prior mean mu(x) is added by the caller (GaussianProcessModel).
#pragma once

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_kernel.h"
#include "odometry_calibration/gp/gp_likelihood.h"

namespace odometry_calibration {

/// M, the inducing inputs of the low-rank variance (chosen from the training inputs by
/// selectInducingInputs with a fixed seed, so a reloaded model predicts the same).
constexpr Eigen::Index kGpVarianceInducingInputs = 200;
/// Exact posteriors on more inputs than this predict their variance through a low-rank
/// projection (O(M^2) per prediction instead of O(n^2)): every size above M.
constexpr Eigen::Index kGpLowRankVarianceInputs = kGpVarianceInducingInputs;
/// Exact posteriors on more inputs than this may project their mean as well (O(M) instead of
/// O(n), if the check at construction passes): the same sizes as the low-rank variance.
constexpr Eigen::Index kGpProjectedMeanInputs = kGpLowRankVarianceInputs;

/// Predictive distribution of f for one output.
class GpPosterior
{
public:
  enum class Kind
  {
    kExact,
    kSparse,
  };

  GpPosterior() = default;

  /// Exact posterior on `inputs` (m x n) with residual targets y - mu_bar and noise variances:
  /// Cholesky of K + S once. Throws std::runtime_error if K + S is not positive definite.
  static GpPosterior exact(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                           const Eigen::MatrixXd& inputs, const Eigen::VectorXd& residuals,
                           const Eigen::VectorXd& noise_variance);
  /// Sparse posterior with inducing inputs Z (m x M), O(n M^2). Throws std::runtime_error if a
  /// factorisation fails.
  static GpPosterior sparse(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                            const Eigen::MatrixXd& inputs, const Eigen::VectorXd& residuals,
                            const Eigen::VectorXd& noise_variance,
                            const Eigen::MatrixXd& inducing_inputs);
  /// Exact posterior of a regression problem with a profiled linear mean: the mean
  /// coefficients C (gp_likelihood.h) come from the same Cholesky factor and are returned;
  /// the posterior is of f given y - H^T C.
  static GpPosterior exact(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                           const GpRegressionData& data, Eigen::VectorXd* mean_coefficients);
  /// Sparse counterpart: C by generalised least squares under Q + S (Woodbury).
  static GpPosterior sparse(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                            const GpRegressionData& data, const Eigen::MatrixXd& inducing_inputs,
                            Eigen::VectorXd* mean_coefficients);
  /// Rebuilds an exact posterior from its saved state (inputs, alpha, noise): the Cholesky
  /// factor is recomputed exactly as in exact(), so predictions are identical.
  static GpPosterior exactFromState(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                    const Eigen::MatrixXd& inputs, const Eigen::VectorXd& alpha,
                                    const Eigen::VectorXd& noise_variance);
  /// Rebuilds a sparse posterior from its saved state (Z, w, V).
  static GpPosterior sparseFromState(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                     const Eigen::MatrixXd& inducing_inputs,
                                     const Eigen::VectorXd& weights,
                                     const Eigen::MatrixXd& variance_matrix);

  /// Posterior mean (without the prior mean) and variance of f at x (m) [target units, ^2].
  void predict(const Eigen::VectorXd& x, double* mean, double* variance) const;
  /// Exact posterior: the variance from the full Cholesky factor, O(n^2), whatever the size
  /// (the reference of the low-rank variance). Sparse: as predict().
  double exactVariance(const Eigen::VectorXd& x) const;
  /// Whether predict() uses the low-rank variance (exact posterior, n > kGpLowRankVarianceInputs).
  bool lowRankVariance() const { return low_rank_variance_.size() > 0; }
  /// Whether predict() uses the projected mean (more than kGpProjectedMeanInputs inputs and the
  /// check passed).
  bool projectedMean() const { return projected_weights_.size() > 0; }
  /// Posterior means at the columns of `inputs`, O(n) each.
  Eigen::VectorXd means(const Eigen::MatrixXd& inputs) const;

  Kind kind() const { return kind_; }
  const GpKernel& kernel() const { return kernel_; }
  const Eigen::VectorXd& logParameters() const { return log_parameters_; }
  /// Training inputs (exact) or inducing inputs (sparse), m x n.
  const Eigen::MatrixXd& basis() const { return basis_; }
  /// alpha (exact) or w (sparse).
  const Eigen::VectorXd& weights() const { return weights_; }
  /// Exact: the noise variances of the training inputs.
  const Eigen::VectorXd& noiseVariance() const { return noise_variance_; }
  /// Sparse: V.
  const Eigen::MatrixXd& varianceMatrix() const { return variance_matrix_; }

private:
  /// A posterior of `kind` over `basis` (the inputs, or the inducing inputs when sparse), with
  /// the kernel and its log-parameters; the rest is filled by the factory functions.
  GpPosterior(Kind kind, const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
              const Eigen::MatrixXd& basis);
  void factorExact();
  /// w_Z and its check (file comment); needs weights_ and the low-rank variance.
  void projectMean();

  Kind kind_ = Kind::kExact;
  GpKernel kernel_;
  Eigen::VectorXd log_parameters_;
  Eigen::MatrixXd basis_;
  Eigen::VectorXd weights_;
  Eigen::VectorXd noise_variance_;     ///< exact
  Eigen::MatrixXd factor_;             ///< exact: lower Cholesky factor of K + S
  Eigen::MatrixXd variance_matrix_;    ///< sparse: V
  Eigen::MatrixXd variance_basis_;     ///< exact, large: Z of the low-rank variance
  Eigen::MatrixXd low_rank_variance_;  ///< exact, large: V_e (empty otherwise)
  Eigen::MatrixXd variance_factor_;    ///< exact, large: lower Cholesky factor of K_ZZ
  Eigen::VectorXd projected_weights_;  ///< exact, large: w_Z if it passed the check
};

}  // namespace odometry_calibration
