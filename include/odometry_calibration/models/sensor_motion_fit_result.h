// The options and the solution of the parametric sensor-motion fits (sensor_motion_fit.h).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// Options of the shared solver.
struct SensorMotionFitOptions
{
  double huber_threshold = 3.0;  ///< on a pair's whitened error norm [sigma]; <= 0: none
  int max_iterations = 500;      ///< Levenberg-Marquardt iteration cap (per solve)
  /// Global starts: the sensor yaw is started at this many evenly spaced angles, the first being
  /// the given start (every 360/n degrees), each solved on at most kScreeningPairs pairs; the
  /// full fit starts from the best of them. 1 (or less): only the given start.
  int yaw_starts = 8;
  /// Whitened error norm beyond which a pair counts as a gross outlier (reported as rejected:
  /// its Huber weight is below huber_threshold / gross_threshold) [sigma].
  double gross_threshold = 5.0;
  /// Rescale the pairs' covariances by a robust estimate of the residual spread (median
  /// whitened error norm against that of unit Gaussian noise) and solve again, so that the
  /// Huber threshold means "n sigma of the actual noise" even when the supplied covariances
  /// (e.g. a scan matcher's) are over- or under-confident.
  bool estimate_noise_scale = true;
};

/// The solution, with everything a report needs.
template <int N>
struct SensorMotionFit
{
  Eigen::Matrix<double, N, 1> intrinsic;
  Pose2 T_base_sensor;
  /// Covariance of (intrinsics, x, y, theta), scaled by chi2_per_dof of the inliers (with
  /// the noise scale applied).
  Eigen::Matrix<double, N + 3, N + 3> covariance = Eigen::Matrix<double, N + 3, N + 3>::Zero();
  bool covariance_available = false;
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
  std::vector<bool> inlier;        ///< per pair: whitened error within the Huber threshold
  double noise_scale = 1.0;        ///< factor applied to the pairs' sigmas (estimate_noise_scale)
  std::size_t outliers = 0;        ///< pairs beyond the Huber threshold (down-weighted)
  std::size_t gross_outliers = 0;  ///< of those, pairs beyond gross_threshold
  int iterations = 0;
  int starts = 1;         ///< starts tried (yaw_starts)
  int starts_agreed = 1;  ///< starts that reached the best minimum (within 1e-4 of its cost)
  bool converged = false;
  std::string termination;
  double solve_time_s = 0.0;
};

}  // namespace odometry_calibration
