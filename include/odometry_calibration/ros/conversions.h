// The thin ROS layer's message conversions: ROS messages in, core types out, and back.
// Only this layer includes ROS headers; the core never does.
#pragma once

#include <string>
#include <vector>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Transform.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {
namespace ros_conversions {

/// Planar part of a 3D transform: x, y and the yaw of the quaternion. Throws
/// std::invalid_argument if the quaternion is not finite or has zero length.
Pose2 fromTransformMsg(const geometry_msgs::Transform& transform);

/// 3D transform of a planar pose (z = 0, rotation about z).
geometry_msgs::Transform toTransformMsg(const Pose2& pose);

/// 3D pose of a planar pose (z = 0, rotation about z).
geometry_msgs::Pose toPoseMsg(const Pose2& pose);

/// A stamped planar pose (negative stamps clamped to 0) in `frame`.
geometry_msgs::PoseStamped toPoseStampedMsg(const Pose2& pose, double stamp_s,
                                            const std::string& frame);

/// Raw readings of the configured joints, in the channels' order, from a JointState's
/// `position` array. Throws std::invalid_argument naming the problem: a name and position
/// array of different lengths, a configured joint missing from the message, a non-finite value.
Eigen::VectorXd rawJointPositions(const sensor_msgs::JointState& message,
                                  const std::vector<EncoderChannelOptions>& channels);

/// The same from the `velocity` array (wheels.source joint_velocity) [position units/s]; also
/// refuses a message with positions but no velocities, saying which source reads those.
Eigen::VectorXd rawJointVelocities(const sensor_msgs::JointState& message,
                                   const std::vector<EncoderChannelOptions>& channels);

/// The core's scan from a LaserScan (ranges copied as they are: the core drops NaN, inf and
/// out-of-range readings). Throws std::invalid_argument for an unusable geometry
/// (angle_increment zero or not finite, range limits not 0 <= min < max).
Scan fromLaserScanMsg(const sensor_msgs::LaserScan& message);

/// Planar pose of a 3D pose (x, y, yaw). Throws std::invalid_argument for a bad quaternion.
Pose2 fromPoseMsg(const geometry_msgs::Pose& pose);

}  // namespace ros_conversions
}  // namespace odometry_calibration
