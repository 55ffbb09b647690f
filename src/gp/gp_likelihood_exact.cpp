#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "odometry_calibration/gp/gp_likelihood.h"

namespace odometry_calibration {
namespace {

constexpr Eigen::Index kDirectBlock = 32;

/// Inverts a lower-triangular matrix in place by blocked recursion (~n^3/3 flops):
/// [A 0; B C]^-1 = [A^-1 0; -C^-1 B A^-1 C^-1]. The strict upper triangle is not touched.
void invertLowerTriangular(Eigen::Ref<Eigen::MatrixXd> l)
{
  const Eigen::Index n = l.rows();
  if (n <= kDirectBlock) {
    Eigen::MatrixXd inverse = Eigen::MatrixXd::Identity(n, n);
    l.triangularView<Eigen::Lower>().solveInPlace(inverse);
    l.triangularView<Eigen::Lower>() = inverse;
    return;
  }
  const Eigen::Index n1 = n / 2;
  const Eigen::Index n2 = n - n1;
  invertLowerTriangular(l.topLeftCorner(n1, n1));
  invertLowerTriangular(l.bottomRightCorner(n2, n2));
  const Eigen::MatrixXd b =
      l.bottomLeftCorner(n2, n1) * l.topLeftCorner(n1, n1).triangularView<Eigen::Lower>();
  l.bottomLeftCorner(n2, n1).noalias() =
      -(l.bottomRightCorner(n2, n2).triangularView<Eigen::Lower>() * b);
}

/// Replaces a lower-triangular M by the lower triangle of M^T M in place (~n^3/3 flops):
/// for M = [A 0; B C], M^T M = [A^T A + B^T B, B^T C; C^T B, C^T C].
void lowerGramOfLowerTriangular(Eigen::Ref<Eigen::MatrixXd> m)
{
  const Eigen::Index n = m.rows();
  if (n <= kDirectBlock) {
    const Eigen::MatrixXd lower = m.triangularView<Eigen::Lower>();
    m.triangularView<Eigen::Lower>() = lower.transpose() * lower;
    return;
  }
  const Eigen::Index n1 = n / 2;
  const Eigen::Index n2 = n - n1;
  const Eigen::MatrixXd ctb =
      m.bottomRightCorner(n2, n2).triangularView<Eigen::Lower>().transpose() *
      m.bottomLeftCorner(n2, n1);
  lowerGramOfLowerTriangular(m.topLeftCorner(n1, n1));
  m.topLeftCorner(n1, n1).selfadjointView<Eigen::Lower>().rankUpdate(
      m.bottomLeftCorner(n2, n1).transpose());
  lowerGramOfLowerTriangular(m.bottomRightCorner(n2, n2));
  m.bottomLeftCorner(n2, n1) = ctb;
}

}  // namespace

Eigen::VectorXd profiledMeanCoefficients(const Eigen::MatrixXd& mean_basis,
                                         const Eigen::MatrixXd& inverse_times_basis,
                                         const Eigen::VectorXd& inverse_times_targets)
{
  const Eigen::Index p = mean_basis.rows();
  if (p == 0) {
    return Eigen::VectorXd();
  }
  Eigen::MatrixXd normal = mean_basis * inverse_times_basis;
  normal = 0.5 * (normal + normal.transpose()).eval();
  const double ridge = 1e-12 * std::max(normal.trace() / static_cast<double>(p), 1e-300);
  normal.diagonal().array() += ridge;
  return normal.ldlt().solve(mean_basis * inverse_times_targets);
}

bool exactLogMarginalLikelihood(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                const GpRegressionData& data, bool with_gradient,
                                GpLikelihood* result)
{
  const Eigen::Index n = data.inputs.cols();
  Eigen::MatrixXd covariance = kernel.gram(log_parameters, data.inputs);
  covariance.diagonal() += data.noise_variance;
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(covariance);  // factor in place
  if (llt.info() != Eigen::Success) {
    return false;
  }

  // alpha = (K + S)^-1 (y - H^T C), C profiled (file comment of gp_likelihood.h).
  Eigen::VectorXd alpha = llt.solve(data.targets);
  result->mean_coefficients.resize(0);
  if (data.mean_basis.rows() > 0) {
    const Eigen::MatrixXd inverse_basis = llt.solve(data.mean_basis.transpose());
    result->mean_coefficients = profiledMeanCoefficients(data.mean_basis, inverse_basis, alpha);
    alpha.noalias() -= inverse_basis * result->mean_coefficients;
  }
  Eigen::VectorXd residual = data.targets;
  if (data.mean_basis.rows() > 0) {
    residual.noalias() -= data.mean_basis.transpose() * result->mean_coefficients;
  }
  constexpr double kLog2Pi = 1.8378770664093453;
  const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  result->value =
      -0.5 * residual.dot(alpha) - 0.5 * log_det - 0.5 * static_cast<double>(n) * kLog2Pi;
  if (!std::isfinite(result->value)) {
    return false;
  }
  if (!with_gradient) {
    return true;
  }

  // W = (K + S)^-1 = L^-T L^-1 from the factor, lower triangle, in the factor's storage.
  Eigen::MatrixXd& weights = covariance;  // holds L; llt is not used below
  invertLowerTriangular(weights);
  lowerGramOfLowerTriangular(weights);
  // Q = 1/2 (alpha alpha^T - W): dL/dK_ij for a symmetric perturbation (lower triangle).
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j; i < n; ++i) {
      weights(i, j) = 0.5 * (alpha(i) * alpha(j) - weights(i, j));
    }
  }
  result->d_kernel = Eigen::VectorXd::Zero(kernel.parameterCount());
  kernel.addGramGradient(log_parameters, data.inputs, weights, &result->d_kernel);
  result->d_noise = weights.diagonal();
  result->d_targets = -alpha;
  return true;
}

}  // namespace odometry_calibration
