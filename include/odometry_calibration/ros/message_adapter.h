// The one input adapter: each ROS message type the calibration takes, made a session input
// (session/converted_input.h) by one function, for the live node's subscriptions and the bag
// reader alike. A message that cannot be converted (a JointState without a configured joint or
// with a NaN, a LaserScan of impossible geometry or too many rays, a PointCloud2 of a broken
// layout or too sparse in the band, a pose whose quaternion is not one) becomes a bad input with
// the reason, which the session skips and counts; the functions never throw for a message's
// content. The session's own checks (usable readings, the cloud's frame) come after, in
// feedInput: one rule for both front ends.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/session/converted_input.h"

namespace odometry_calibration {

/// Converts messages for one configuration (joints, signs, ray limit, cloud filter). Each
/// input names the message's `publisher` (moved in; empty: unknown).
class MessageAdapter
{
public:
  explicit MessageAdapter(const CalibrationConfig& config);

  /// The configured joints' raw positions with their signs, or kBadJoints naming the problem
  /// (mismatched name and position arrays, a missing joint, a value that is not finite). With
  /// wheels.source joint_velocity: their velocities (kJointVelocities, no signs), or kBadJoints.
  ConvertedInput convert(const sensor_msgs::JointState& message, std::string publisher) const;
  /// wheels.source ticks: joint `wheel`'s raw reading `value` from its std_msgs topic, which
  /// carries no stamp: `time_s` is the receive time (live) or the record time (bag) [s].
  /// kWheelTick, or kBadJoints for a value that is not finite (the unwrapper checks the rest).
  ConvertedInput convertWheelTick(double value, std::size_t wheel, double time_s,
                                  std::string publisher) const;
  /// wheels.source odometry: the base's own odometry pose (kBaseOdometry, stamped by its
  /// header), or kBadJoints for a quaternion that is not finite or of zero length.
  ConvertedInput convertBaseOdometry(const nav_msgs::Odometry& message,
                                     std::string publisher) const;
  /// Source `source`'s scan, or kBadEgoMessage: more rays than ego_motion.max_scan_rays
  /// (refused before the ranges are copied), an impossible geometry.
  ConvertedInput convert(const sensor_msgs::LaserScan& message, std::size_t source,
                         std::string publisher) const;
  /// Source `source`'s cloud cut into a planar scan (kCloudScan, the per-point time problem in
  /// `problem`), or kBadEgoMessage: a broken layout, too few points in the band, a build without
  /// PCL (scan/pcl_support.h). Adds the time spent filtering the cloud into a scan to
  /// `filtering_s` when given [s].
  ConvertedInput convert(const sensor_msgs::PointCloud2& message, std::size_t source,
                         std::string publisher, double* filtering_s = nullptr) const;
  /// Source `source`'s sensor pose (the pose, the child frame), or kBadEgoMessage ("pose") for
  /// a quaternion that is not finite or of zero length.
  ConvertedInput convert(const nav_msgs::Odometry& message, std::size_t source,
                         std::string publisher) const;
  /// Source `source`'s sensor pose (no frame), or kBadEgoMessage ("pose") as for Odometry.
  ConvertedInput convert(const geometry_msgs::PoseStamped& message, std::size_t source,
                         std::string publisher) const;
  /// gyro.topic's reading: its stamp and angular velocity in its frame (kGyro; the session's
  /// GyroSource checks the values).
  ConvertedInput convert(const sensor_msgs::Imu& message, std::string publisher) const;

private:
  CalibrationConfig config_;
  std::vector<EncoderChannelOptions> channels_;
};

}  // namespace odometry_calibration
