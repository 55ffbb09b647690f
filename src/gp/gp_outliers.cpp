#include "odometry_calibration/gp/gp_outliers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "odometry_calibration/common/median.h"

namespace odometry_calibration {
namespace {

/// Appends the monomials of exactly `degree` with variable indices >= `first`.
void appendMonomials(const Eigen::MatrixXd& inputs, int degree, Eigen::Index first,
                     const Eigen::RowVectorXd& product, std::vector<Eigen::RowVectorXd>* rows)
{
  if (degree == 0) {
    rows->push_back(product);
    return;
  }
  for (Eigen::Index p = first; p < inputs.rows(); ++p) {
    appendMonomials(inputs, degree - 1, p, product.cwiseProduct(inputs.row(p)), rows);
  }
}

}  // namespace

int polynomialTermCount(int m, int degree)
{
  // C(m + degree, degree).
  double count = 1.0;
  for (int k = 1; k <= degree; ++k) {
    count = count * (m + k) / k;
  }
  return static_cast<int>(std::lround(count));
}

Eigen::MatrixXd polynomialFeatures(const Eigen::MatrixXd& inputs, int degree)
{
  std::vector<Eigen::RowVectorXd> rows;
  const Eigen::RowVectorXd ones = Eigen::RowVectorXd::Ones(inputs.cols());
  for (int d = 0; d <= degree; ++d) {
    appendMonomials(inputs, d, 0, ones, &rows);
  }
  Eigen::MatrixXd features(static_cast<Eigen::Index>(rows.size()), inputs.cols());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    features.row(static_cast<Eigen::Index>(r)) = rows[r];
  }
  return features;
}

namespace {

/// The highest polynomial degree (3, 2 or 1) with at least 20 pairs per term for `n` pairs of
/// `m` inputs; 1 when even that has fewer.
int prefitDegree(Eigen::Index n, int m)
{
  for (int degree = 3; degree >= 1; --degree) {
    if (n >= 20 * static_cast<Eigen::Index>(polynomialTermCount(m, degree))) {
      return degree;
    }
  }
  return 1;
}

/// One axis' iteratively reweighted fit of the polynomial `features` (terms x n) to `y` with
/// standard deviations `sigma`: Huber weights on the residuals scaled by sigma and by their
/// robust (MAD) scale, at most `iterations` times. Returns the residuals; the final robust
/// scale goes to `scale`.
Eigen::VectorXd huberPolynomialResiduals(const Eigen::MatrixXd& features, const Eigen::VectorXd& y,
                                         const Eigen::VectorXd& sigma, double huber_threshold,
                                         int iterations, double* scale)
{
  const Eigen::Index n = y.size();
  Eigen::VectorXd robust = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd residual = y;
  *scale = 1.0;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const Eigen::VectorXd weight = robust.cwiseQuotient(sigma.cwiseAbs2());
    Eigen::MatrixXd normal = features * weight.asDiagonal() * features.transpose();
    normal.diagonal().array() += 1e-12 * std::max(normal.trace(), 1e-300);
    const Eigen::VectorXd coefficients = normal.ldlt().solve(features * weight.cwiseProduct(y));
    const Eigen::VectorXd next = y - features.transpose() * coefficients;
    const Eigen::VectorXd scaled = next.cwiseQuotient(sigma);
    std::vector<double> magnitudes(scaled.data(), scaled.data() + n);
    for (double& v : magnitudes) {
      v = std::abs(v);
    }
    *scale = std::max(1.4826 * median(magnitudes), 1e-9);
    // Huber weights: 1 inside the threshold, threshold/|u| beyond.
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = std::abs(scaled(i)) / *scale;
      robust(i) = u <= huber_threshold ? 1.0 : huber_threshold / u;
    }
    const double change = (next - residual).cwiseQuotient(sigma).cwiseAbs().maxCoeff();
    residual = next;
    if (iteration > 0 && change < 1e-6 * *scale) {
      break;
    }
  }
  return residual;
}

}  // namespace

GpPrefitResult robustPolynomialPrefit(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                                      const Eigen::MatrixXd& variances, double huber_threshold,
                                      double outlier_threshold, int iterations)
{
  const Eigen::Index n = inputs.cols();
  if (targets.cols() != n || variances.cols() != n || targets.rows() != 3 ||
      variances.rows() != 3) {
    throw std::invalid_argument("gp pre-fit: targets and variances must be 3 x n");
  }
  GpPrefitResult result;
  result.degree = prefitDegree(n, static_cast<int>(inputs.rows()));
  const Eigen::MatrixXd features = polynomialFeatures(inputs, result.degree);
  result.residuals.resize(3, n);
  result.inlier.assign(static_cast<std::size_t>(n), true);
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::VectorXd y = targets.row(axis).transpose();
    const Eigen::VectorXd sigma = variances.row(axis).transpose().cwiseMax(1e-300).cwiseSqrt();
    double scale = 1.0;
    const Eigen::VectorXd residual =
        huberPolynomialResiduals(features, y, sigma, huber_threshold, iterations, &scale);
    result.residuals.row(axis) = residual.transpose();
    result.robust_scale(axis) = scale;
    if (outlier_threshold > 0.0) {
      for (Eigen::Index i = 0; i < n; ++i) {
        if (std::abs(residual(i)) / (sigma(i) * scale) > outlier_threshold) {
          result.inlier[static_cast<std::size_t>(i)] = false;
        }
      }
    }
  }
  return result;
}

}  // namespace odometry_calibration
