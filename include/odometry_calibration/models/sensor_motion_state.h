// What a fitted sensor-motion model (differential drive, mecanum) holds: its N intrinsic
// parameters, the sensor's pose on the robot, their joint covariance and the covariance its
// predictions carry. Fitted by parametric_model.h's fitParametricModel, which updates it.
#pragma once

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

template <int N>
struct SensorMotionState
{
  Eigen::Matrix<double, N, 1> intrinsics;  ///< the kinematics' parameters (units: the model's)
  Pose2 T_base_sensor;                     ///< the sensor's pose in base_link [m, m, rad]
  /// Covariance of (intrinsics, x, y, theta); zero until a fit succeeds.
  Eigen::Matrix<double, N + 3, N + 3> covariance = Eigen::Matrix<double, N + 3, N + 3>::Zero();
  /// The fit's per-pair residual spread, added to every prediction [m^2, rad^2].
  Eigen::Matrix3d prediction_covariance = Eigen::Matrix3d::Zero();
};

}  // namespace odometry_calibration
