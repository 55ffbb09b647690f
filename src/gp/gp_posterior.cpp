#include "odometry_calibration/gp/gp_posterior.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "odometry_calibration/gp/gp_inducing.h"
#include "odometry_calibration/gp/gp_likelihood.h"

namespace odometry_calibration {
namespace {

/// k^T V k for a symmetric V from its lower triangle only: sum_j k_j (V_jj k_j + 2 sum_{i>j}
/// V_ij k_i). Half the reads and multiplications of the full product V k (the O(M^2) part of a
/// low-rank variance), the same sum up to rounding order.
double symmetricQuadraticForm(const Eigen::MatrixXd& v, const Eigen::VectorXd& k)
{
  const Eigen::Index m = k.size();
  double sum = 0.0;
  for (Eigen::Index j = 0; j < m; ++j) {
    const Eigen::Index below = m - j - 1;
    const double off_diagonal = v.col(j).tail(below).dot(k.tail(below));
    sum += k(j) * (v(j, j) * k(j) + 2.0 * off_diagonal);
  }
  return sum;
}

/// The targets minus the profiled mean, r = y - H^T C, with the mean's coefficients
/// C = (H S^-1 H^T)^-1 H S^-1 y (profiledMeanCoefficients) written to *mean_coefficients, where
/// apply_inverse(v) = S^-1 v for the posterior's covariance S of the targets (K + Sigma, or its
/// sparse approximation). Without a mean basis (p = 0): r = y and C empty.
template <typename ApplyInverse>
Eigen::VectorXd subtractProfiledMean(const GpRegressionData& data,
                                     const ApplyInverse& apply_inverse,
                                     Eigen::VectorXd* mean_coefficients)
{
  Eigen::VectorXd residuals = data.targets;
  mean_coefficients->resize(0);
  if (data.mean_basis.rows() > 0) {
    *mean_coefficients =
        profiledMeanCoefficients(data.mean_basis, apply_inverse(data.mean_basis.transpose()),
                                 apply_inverse(data.targets).col(0));
    residuals.noalias() -= data.mean_basis.transpose() * *mean_coefficients;
  }
  return residuals;
}

}  // namespace

GpPosterior::GpPosterior(Kind kind, const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                         const Eigen::MatrixXd& basis)
    : kind_(kind), kernel_(kernel), log_parameters_(log_parameters), basis_(basis)
{
}

void GpPosterior::factorExact()
{
  Eigen::MatrixXd covariance = kernel_.gram(log_parameters_, basis_);
  covariance.diagonal() += noise_variance_;
  Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("gp: K + Sigma is not positive definite (degenerate hyperparameters)");
  }
  factor_ = llt.matrixL();
  variance_basis_.resize(0, 0);
  low_rank_variance_.resize(0, 0);
  if (basis_.cols() <= kGpLowRankVarianceInputs)
    return;
  // V_e = K_ZZ^-1 K_Zn (K + S)^-1 K_nZ K_ZZ^-1, with (K + S)^-1 = L^-T L^-1: O(n^2 M) once.
  variance_basis_ = selectInducingInputs(basis_, kGpVarianceInducingInputs, 7u);
  Eigen::MatrixXd l_z;
  if (!factorInducingCovariance(kernel_.gram(log_parameters_, variance_basis_), &l_z)) {
    variance_basis_.resize(0, 0);
    return;  // keep the exact variance
  }
  Eigen::MatrixXd w = kernel_.cross(log_parameters_, basis_, variance_basis_);  // n x M
  factor_.triangularView<Eigen::Lower>().solveInPlace(w);                       // L^-1 K_nZ
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(w.cols(), w.cols());
  p.selfadjointView<Eigen::Lower>().rankUpdate(w.transpose());
  p = p.selfadjointView<Eigen::Lower>();
  const auto lower_z = l_z.triangularView<Eigen::Lower>();
  const auto upper_z = l_z.transpose().triangularView<Eigen::Upper>();
  lower_z.solveInPlace(p);            // L_z^-1 P
  Eigen::MatrixXd q = p.transpose();  // P L_z^-T
  lower_z.solveInPlace(q);            // L_z^-1 P L_z^-T (symmetric)
  upper_z.solveInPlace(q);            // L_z^-T L_z^-1 P L_z^-T
  Eigen::MatrixXd v = q.transpose();
  upper_z.solveInPlace(v);  // K_ZZ^-1 P K_ZZ^-1
  low_rank_variance_ = 0.5 * (v + v.transpose());
  variance_factor_ = l_z;
}

void GpPosterior::projectMean()
{
  projected_weights_.resize(0);
  if (low_rank_variance_.size() == 0 || basis_.cols() <= kGpProjectedMeanInputs)
    return;
  Eigen::VectorXd w = kernel_.cross(log_parameters_, variance_basis_, basis_) * weights_;
  variance_factor_.triangularView<Eigen::Lower>().solveInPlace(w);
  variance_factor_.transpose().triangularView<Eigen::Upper>().solveInPlace(w);
  const double tolerance = 0.01 * std::sqrt(noise_variance_.minCoeff());
  const Eigen::Index step = std::max<Eigen::Index>(1, basis_.cols() / 256);
  for (Eigen::Index i = 0; i < basis_.cols(); i += step) {
    const Eigen::VectorXd x = basis_.col(i);
    const double exact = kernel_.column(log_parameters_, basis_, x).dot(weights_);
    const double projected = kernel_.column(log_parameters_, variance_basis_, x).dot(w);
    if (!(std::abs(exact - projected) <= tolerance))
      return;  // keep the exact mean
  }
  projected_weights_ = w;
}

GpPosterior GpPosterior::exact(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                               const Eigen::MatrixXd& inputs, const Eigen::VectorXd& residuals,
                               const Eigen::VectorXd& noise_variance)
{
  const GpRegressionData data{inputs, residuals, noise_variance, Eigen::MatrixXd(0, inputs.cols())};
  Eigen::VectorXd unused;
  return exact(kernel, log_parameters, data, &unused);
}

GpPosterior GpPosterior::exact(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                               const GpRegressionData& data, Eigen::VectorXd* mean_coefficients)
{
  GpPosterior posterior(Kind::kExact, kernel, log_parameters, data.inputs);
  posterior.noise_variance_ = data.noise_variance;
  posterior.factorExact();
  const auto lower = posterior.factor_.triangularView<Eigen::Lower>();
  const auto upper = posterior.factor_.transpose().triangularView<Eigen::Upper>();
  const auto apply_inverse = [&](Eigen::MatrixXd v) {
    lower.solveInPlace(v);
    upper.solveInPlace(v);
    return v;
  };
  const Eigen::VectorXd residuals = subtractProfiledMean(data, apply_inverse, mean_coefficients);
  posterior.weights_ = apply_inverse(residuals).col(0);
  posterior.projectMean();
  return posterior;
}

GpPosterior GpPosterior::exactFromState(const GpKernel& kernel,
                                        const Eigen::VectorXd& log_parameters,
                                        const Eigen::MatrixXd& inputs, const Eigen::VectorXd& alpha,
                                        const Eigen::VectorXd& noise_variance)
{
  if (alpha.size() != inputs.cols() || noise_variance.size() != inputs.cols()) {
    throw std::runtime_error("gp: exact posterior needs one weight and one noise per input");
  }
  GpPosterior posterior(Kind::kExact, kernel, log_parameters, inputs);
  posterior.noise_variance_ = noise_variance;
  posterior.weights_ = alpha;
  posterior.factorExact();
  posterior.projectMean();
  return posterior;
}

GpPosterior GpPosterior::sparse(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                const Eigen::MatrixXd& inputs, const Eigen::VectorXd& residuals,
                                const Eigen::VectorXd& noise_variance,
                                const Eigen::MatrixXd& inducing_inputs)
{
  const GpRegressionData data{inputs, residuals, noise_variance, Eigen::MatrixXd(0, inputs.cols())};
  Eigen::VectorXd unused;
  return sparse(kernel, log_parameters, data, inducing_inputs, &unused);
}

GpPosterior GpPosterior::sparse(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                                const GpRegressionData& data,
                                const Eigen::MatrixXd& inducing_inputs,
                                Eigen::VectorXd* mean_coefficients)
{
  const Eigen::Index m = inducing_inputs.cols();
  Eigen::MatrixXd l_m;
  if (!factorInducingCovariance(kernel.gram(log_parameters, inducing_inputs), &l_m)) {
    throw std::runtime_error("gp: the inducing covariance is not positive definite");
  }
  const Eigen::VectorXd inv_sqrt_noise = data.noise_variance.array().rsqrt();
  Eigen::MatrixXd a = kernel.cross(log_parameters, inducing_inputs, data.inputs);
  l_m.triangularView<Eigen::Lower>().solveInPlace(a);
  a = a * inv_sqrt_noise.asDiagonal();
  Eigen::MatrixXd b = Eigen::MatrixXd::Identity(m, m);
  b.selfadjointView<Eigen::Lower>().rankUpdate(a);
  Eigen::LLT<Eigen::MatrixXd> llt_b(b);
  if (llt_b.info() != Eigen::Success) {
    throw std::runtime_error("gp: the sparse posterior's system is not positive definite");
  }
  // (Q + S)^-1 v = S^-1 v - S^-1/2 A^T B^-1 A S^-1/2 v for the mean's least squares.
  const auto apply_inverse = [&](const Eigen::MatrixXd& v) {
    const Eigen::MatrixXd scaled = inv_sqrt_noise.asDiagonal() * v;
    const Eigen::MatrixXd out = scaled - a.transpose() * llt_b.solve(a * scaled);
    return Eigen::MatrixXd(inv_sqrt_noise.asDiagonal() * out);
  };
  const Eigen::VectorXd residuals = subtractProfiledMean(data, apply_inverse, mean_coefficients);
  const auto upper_m = l_m.transpose().triangularView<Eigen::Upper>();
  GpPosterior posterior(Kind::kSparse, kernel, log_parameters, inducing_inputs);
  // w = L_m^-T B^-1 A S^-1/2 r.
  posterior.weights_ = llt_b.solve(a * inv_sqrt_noise.cwiseProduct(residuals));
  upper_m.solveInPlace(posterior.weights_);
  // V = L_m^-T (I - B^-1) L_m^-1.
  Eigen::MatrixXd middle =
      Eigen::MatrixXd::Identity(m, m) - llt_b.solve(Eigen::MatrixXd::Identity(m, m));
  upper_m.solveInPlace(middle);
  Eigen::MatrixXd v = middle.transpose();
  upper_m.solveInPlace(v);
  posterior.variance_matrix_ = 0.5 * (v + v.transpose());
  return posterior;
}

GpPosterior GpPosterior::sparseFromState(const GpKernel& kernel,
                                         const Eigen::VectorXd& log_parameters,
                                         const Eigen::MatrixXd& inducing_inputs,
                                         const Eigen::VectorXd& weights,
                                         const Eigen::MatrixXd& variance_matrix)
{
  const Eigen::Index m = inducing_inputs.cols();
  if (weights.size() != m || variance_matrix.rows() != m || variance_matrix.cols() != m) {
    throw std::runtime_error("gp: sparse posterior needs M weights and an M x M variance matrix");
  }
  GpPosterior posterior(Kind::kSparse, kernel, log_parameters, inducing_inputs);
  posterior.weights_ = weights;
  posterior.variance_matrix_ = variance_matrix;
  return posterior;
}

void GpPosterior::predict(const Eigen::VectorXd& x, double* mean, double* variance) const
{
  if (projected_weights_.size() > 0) {  // O(M^2), no O(n) kernel column
    const Eigen::VectorXd k_z = kernel_.column(log_parameters_, variance_basis_, x);
    *mean = k_z.dot(projected_weights_);
    const double prior = kernel_.diagonal(log_parameters_, x)(0);
    *variance = std::max(prior - symmetricQuadraticForm(low_rank_variance_, k_z), 0.0);
    return;
  }
  const Eigen::VectorXd k = kernel_.column(log_parameters_, basis_, x);
  const double prior = kernel_.diagonal(log_parameters_, x)(0);
  *mean = k.dot(weights_);
  double explained = 0.0;
  if (kind_ == Kind::kExact && low_rank_variance_.size() > 0) {
    const Eigen::VectorXd k_z = kernel_.column(log_parameters_, variance_basis_, x);
    explained = symmetricQuadraticForm(low_rank_variance_, k_z);
  } else if (kind_ == Kind::kExact) {
    explained = factor_.triangularView<Eigen::Lower>().solve(k).squaredNorm();
  } else {
    explained = k.dot(variance_matrix_ * k);
  }
  *variance = std::max(prior - explained, 0.0);
}

double GpPosterior::exactVariance(const Eigen::VectorXd& x) const
{
  const Eigen::VectorXd k = kernel_.column(log_parameters_, basis_, x);
  const double prior = kernel_.diagonal(log_parameters_, x)(0);
  const double explained = kind_ == Kind::kExact
                               ? factor_.triangularView<Eigen::Lower>().solve(k).squaredNorm()
                               : k.dot(variance_matrix_ * k);
  return std::max(prior - explained, 0.0);
}

Eigen::VectorXd GpPosterior::means(const Eigen::MatrixXd& inputs) const
{
  Eigen::VectorXd out(inputs.cols());
  // Blocks keep the kernel matrix small for many inputs.
  constexpr Eigen::Index kBlock = 512;
  for (Eigen::Index start = 0; start < inputs.cols(); start += kBlock) {
    const Eigen::Index count = std::min(kBlock, inputs.cols() - start);
    out.segment(start, count) =
        kernel_.cross(log_parameters_, inputs.middleCols(start, count), basis_) * weights_;
  }
  return out;
}

}  // namespace odometry_calibration
