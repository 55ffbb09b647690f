// Log marginal likelihood of one GP output (paper eqs. 3-4: s_hat ~ N(mu_bar, K + Sigma)) and its
// sparse variational lower bound (VFE, Titsias 2009), with analytic gradients.
//
// The linear mean mu(x) = C x (paper eq. 6) is profiled: for given kernel parameters and noise,
// the likelihood is a concave quadratic in C, maximised in closed form by generalised least
// squares, C = (H S^-1 H^T)^-1 H S^-1 y with S the marginal covariance. The returned gradient is
// the partial one at that C, which equals the total derivative of the profiled likelihood (the
// C-derivative vanishes there), so C behaves as a hyperparameter optimised jointly.
#pragma once

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_kernel.h"

namespace odometry_calibration {

/// One output's regression problem: y_i = mu(x_i) + f(x_i) + e_i, e_i ~ N(0, noise_variance_i).
struct GpRegressionData
{
  Eigen::MatrixXd inputs;          ///< m x n inputs (columns)
  Eigen::VectorXd targets;         ///< n targets y
  Eigen::VectorXd noise_variance;  ///< n noise variances (> 0)
  /// p x n basis of the mean function (rows: one per coefficient, e.g. the inputs for the
  /// linear mean); 0 x n for the zero mean.
  Eigen::MatrixXd mean_basis;
};

/// Value and partial derivatives of a (bound on the) log marginal likelihood.
struct GpLikelihood
{
  double value = 0.0;                 ///< log p(y) (exact) or its VFE lower bound
  Eigen::VectorXd mean_coefficients;  ///< the profiled C (p)
  Eigen::VectorXd d_kernel;           ///< d value / d kernel log-parameters
  Eigen::VectorXd d_targets;          ///< d value / d y_i
  Eigen::VectorXd d_noise;            ///< d value / d noise_variance_i
};

/// Exact log marginal likelihood log N(y | H^T C, K + diag(noise)) with C profiled, and (if
/// `with_gradient`) its derivatives: d/d theta = 1/2 tr((alpha alpha^T - (K+S)^-1) dK/d theta)
/// (Rasmussen & Williams eq. 5.9). O(n^3). Returns false if K + diag(noise) is not positive
/// definite in floating point.
bool exactLogMarginalLikelihood(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                const GpRegressionData& data, bool with_gradient,
                                GpLikelihood* result);

/// The VFE bound log N(y | H^T C, Q + diag(noise)) - 1/2 sum_i (k_ii - q_ii) / noise_i with
/// Q = K_nm K_mm^-1 K_mn for inducing inputs Z (m x M), C profiled, and its derivatives. Equal to
/// the exact likelihood when Z are the training inputs. O(n M^2). Returns false if a
/// factorisation fails.
bool vfeLogLikelihoodBound(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                           const GpRegressionData& data, const Eigen::MatrixXd& inducing_inputs,
                           bool with_gradient, GpLikelihood* result);

/// Generalised least squares for the profiled mean: C = (H S^-1 H^T)^-1 H S^-1 y from the basis
/// H (p x n), S^-1 H^T (n x p) and S^-1 y (n). A relative ridge of 1e-12 keeps a degenerate
/// basis (e.g. a joint that never moved) solvable. Empty for p = 0.
Eigen::VectorXd profiledMeanCoefficients(const Eigen::MatrixXd& mean_basis,
                                         const Eigen::MatrixXd& inverse_times_basis,
                                         const Eigen::VectorXd& inverse_times_targets);

/// Cholesky factor of the inducing covariance K_mm with a jitter on the diagonal, starting at
/// 1e-10 of its mean diagonal and growing tenfold until the factorisation succeeds (at most
/// 1e-4). Returns false if it never does.
bool factorInducingCovariance(const Eigen::MatrixXd& k_mm, Eigen::MatrixXd* lower_factor);

/// First relative jitter tried by factorInducingCovariance.
constexpr double kGpInducingJitterStart = 1e-10;

}  // namespace odometry_calibration
