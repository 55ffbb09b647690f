#include "odometry_calibration/geometry/se2.h"

#include <cmath>

namespace odometry_calibration {

Pose2 se2Exp(const Eigen::Vector3d& xi)
{
  const double theta = xi.z();
  double a = 1.0;  // sin(theta) / theta
  double b = 0.0;  // (1 - cos(theta)) / theta
  if (std::abs(theta) > 1e-9) {
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta;
  } else {
    b = 0.5 * theta;
  }
  return Pose2(a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y(), theta);
}

Eigen::Vector3d se2Log(const Pose2& step)
{
  const double theta = step.theta();
  // V(theta) = [a -b; b a] with a = sin(theta)/theta, b = (1 - cos(theta))/theta; t = V v.
  const double a = std::abs(theta) < 1e-9 ? 1.0 : std::sin(theta) / theta;
  const double b = std::abs(theta) < 1e-9 ? 0.5 * theta : (1.0 - std::cos(theta)) / theta;
  const double det = a * a + b * b;
  return Eigen::Vector3d((a * step.x() + b * step.y()) / det, (-b * step.x() + a * step.y()) / det,
                         theta);
}

Eigen::Matrix3d composeCovariance(const Pose2& a, const Eigen::Matrix3d& covariance_a,
                                  const Pose2& d, const Eigen::Matrix3d& covariance_d)
{
  const double c = std::cos(a.theta()), s = std::sin(a.theta());
  Eigen::Matrix3d J_a = Eigen::Matrix3d::Identity();
  J_a(0, 2) = -s * d.x() - c * d.y();
  J_a(1, 2) = c * d.x() - s * d.y();
  Eigen::Matrix3d J_d = Eigen::Matrix3d::Identity();
  J_d.topLeftCorner<2, 2>() << c, -s, s, c;
  return J_a * covariance_a * J_a.transpose() + J_d * covariance_d * J_d.transpose();
}

}  // namespace odometry_calibration
