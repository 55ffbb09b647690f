// The part of a parametric model's YAML that every sensor-motion model shares: the sensor's pose
// on the robot and the covariance its predictions carry (the fit's residual spread).
#pragma once

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace YAML {
class Emitter;
class Node;
}  // namespace YAML

namespace odometry_calibration {

/// What the keys hold.
struct SensorPoseYaml
{
  Pose2 T_base_sensor;                    ///< [m, m, rad]
  Eigen::Matrix3d prediction_covariance;  ///< added to every prediction [m^2, rad^2]
};

/// Writes `T_base_sensor: [x, y, theta]` and `prediction_covariance: [9 values, row-major]`
/// into the open map of `out`.
void emitSensorPoseYaml(YAML::Emitter& out, const Pose2& T_base_sensor,
                        const Eigen::Matrix3d& prediction_covariance);

/// Reads the two keys back. Throws std::runtime_error when a count is wrong (and what yaml-cpp
/// throws for a missing key or a non-number).
SensorPoseYaml readSensorPoseYaml(const YAML::Node& node);

}  // namespace odometry_calibration
