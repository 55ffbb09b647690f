#include "odometry_calibration/ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/name_list.h"

namespace odometry_calibration {
namespace ros_conversions {

Pose2 fromTransformMsg(const geometry_msgs::Transform& transform)
{
  const auto& q = transform.rotation;
  const double norm2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  if (!std::isfinite(norm2) || norm2 < 1e-12) {
    throw std::invalid_argument("transform rotation is not a valid quaternion");
  }
  const double yaw =
      std::atan2(2.0 * (q.w * q.z + q.x * q.y), norm2 - 2.0 * (q.y * q.y + q.z * q.z));
  return Pose2(transform.translation.x, transform.translation.y, yaw);
}

geometry_msgs::Transform toTransformMsg(const Pose2& pose)
{
  geometry_msgs::Transform transform;
  transform.translation.x = pose.x();
  transform.translation.y = pose.y();
  transform.translation.z = 0.0;
  transform.rotation.x = 0.0;
  transform.rotation.y = 0.0;
  transform.rotation.z = std::sin(0.5 * pose.theta());
  transform.rotation.w = std::cos(0.5 * pose.theta());
  return transform;
}

geometry_msgs::Pose toPoseMsg(const Pose2& pose)
{
  const geometry_msgs::Transform transform = toTransformMsg(pose);
  geometry_msgs::Pose result;
  result.position.x = transform.translation.x;
  result.position.y = transform.translation.y;
  result.position.z = 0.0;
  result.orientation = transform.rotation;
  return result;
}

namespace {

/// The configured channels' values from `values` (`what`: "position" or "velocity"), found by
/// the message's names.
Eigen::VectorXd namedJointValues(const sensor_msgs::JointState& message,
                                 const std::vector<double>& values, const std::string& what,
                                 const std::vector<EncoderChannelOptions>& channels)
{
  if (message.name.size() != values.size()) {
    throw std::invalid_argument("JointState has " + std::to_string(message.name.size()) +
                                " names but " + std::to_string(values.size()) + " " + what + "s");
  }
  Eigen::VectorXd raw(static_cast<Eigen::Index>(channels.size()));
  for (std::size_t c = 0; c < channels.size(); ++c) {
    std::size_t found = message.name.size();
    for (std::size_t i = 0; i < message.name.size(); ++i) {
      if (message.name[i] == channels[c].name) {
        found = i;
        break;
      }
    }
    if (found == message.name.size()) {
      throw std::invalid_argument("JointState lacks the configured joint '" + channels[c].name +
                                  "': it has " + quotedNames(message.name));
    }
    const double value = values[found];
    if (!std::isfinite(value)) {
      throw std::invalid_argument("JointState " + what + " of joint '" + channels[c].name +
                                  "' is not a finite number");
    }
    raw(static_cast<Eigen::Index>(c)) = value;
  }
  return raw;
}

}  // namespace

Eigen::VectorXd rawJointPositions(const sensor_msgs::JointState& message,
                                  const std::vector<EncoderChannelOptions>& channels)
{
  return namedJointValues(message, message.position, "position", channels);
}

Eigen::VectorXd rawJointVelocities(const sensor_msgs::JointState& message,
                                   const std::vector<EncoderChannelOptions>& channels)
{
  if (!message.position.empty() && message.velocity.empty()) {
    throw std::invalid_argument(
        "JointState has positions but no velocities: wheels.source joint_velocity reads "
        "`velocity`; set wheels.source joint_state to use the positions");
  }
  return namedJointValues(message, message.velocity, "velocity", channels);
}

Scan fromLaserScanMsg(const sensor_msgs::LaserScan& message)
{
  Scan scan;
  scan.angle_min_rad = message.angle_min;
  scan.angle_increment_rad = message.angle_increment;
  scan.range_min_m = message.range_min;
  scan.range_max_m = message.range_max;
  scan.ranges_m.assign(message.ranges.begin(), message.ranges.end());
  scan.time_increment_s = message.time_increment;
  validate(scan);
  return scan;
}

Pose2 fromPoseMsg(const geometry_msgs::Pose& pose)
{
  geometry_msgs::Transform transform;
  transform.translation.x = pose.position.x;
  transform.translation.y = pose.position.y;
  transform.rotation = pose.orientation;
  return fromTransformMsg(transform);
}

geometry_msgs::PoseStamped toPoseStampedMsg(const Pose2& pose, double stamp_s,
                                            const std::string& frame)
{
  geometry_msgs::PoseStamped msg;
  msg.header.stamp = ros::Time(std::max(0.0, stamp_s));
  msg.header.frame_id = frame;
  msg.pose = toPoseMsg(pose);
  return msg;
}

}  // namespace ros_conversions
}  // namespace odometry_calibration
