// Outlier screening of keyframe pairs before the GP is fitted. Real pairs contain scan-matching
// failures (1-4 % gross outliers) and a Gaussian likelihood is not robust to them, so each output
// is first fitted by a polynomial in the encoder features (a generic, kinematics-free stand-in
// for f) with iteratively reweighted least squares under the Huber loss, residuals scaled by the
// pair's sigma (as in the paper's eq. 9). Pairs beyond a threshold of the robust residual spread
// on any axis are outliers. GaussianProcessModel then re-checks all pairs against its own
// prediction.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace odometry_calibration {

/// Result of the robust pre-fit.
struct GpPrefitResult
{
  std::vector<bool> inlier;      ///< per pair
  Eigen::Vector3d robust_scale;  ///< per axis: 1.4826 MAD of the sigma-scaled residuals
  Eigen::MatrixXd residuals;     ///< 3 x n residuals y - polynomial
  int degree = 1;                ///< polynomial degree used
};

/// Number of monomials of total degree <= `degree` in `m` variables (with the constant).
int polynomialTermCount(int m, int degree);

/// All monomials of total degree <= `degree` of the columns of `inputs` (m x n): a
/// polynomialTermCount x n matrix, the constant first.
Eigen::MatrixXd polynomialFeatures(const Eigen::MatrixXd& inputs, int degree);

/// Huber-IRLS pre-fit of each row of `targets` (3 x n, known variances `variances` 3 x n > 0) on
/// a polynomial of the inputs (m x n, scaled to unit spread) of degree 3, 2 or 1, the highest
/// with at least 20 pairs per coefficient. Pairs with |residual| / (sigma * robust scale) above
/// `outlier_threshold` on any axis are outliers (<= 0: none).
GpPrefitResult robustPolynomialPrefit(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                                      const Eigen::MatrixXd& variances, double huber_threshold,
                                      double outlier_threshold, int iterations = 30);

}  // namespace odometry_calibration
