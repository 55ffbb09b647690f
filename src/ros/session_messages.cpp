#include "odometry_calibration/ros/session_messages.h"

#include <algorithm>

#include <ros/console.h>

#include "odometry_calibration/ros/conversions.h"

namespace odometry_calibration {
namespace ros_conversions {
namespace {

/// (x, y, yaw) covariance into ROS's 6x6 (x y z roll pitch yaw); z, roll, pitch not estimated.
void setCovariance(boost::array<double, 36>* out, const Eigen::Matrix3d& covariance)
{
  const int index[3] = {0, 1, 5};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      (*out)[6 * index[r] + index[c]] = covariance(r, c);
  for (int i : {2, 3, 4})
    (*out)[7 * i] = 1e6;
}

}  // namespace

void logToRos(SessionLogLevel level, const std::string& text)
{
  if (level == SessionLogLevel::kInfo)
    ROS_INFO("%s", text.c_str());
  else if (level == SessionLogLevel::kWarn)
    ROS_WARN("%s", text.c_str());
  else
    ROS_ERROR("%s", text.c_str());
}

nav_msgs::Odometry toOdometryMsg(const OdometryState& state, const std::string& odom_frame,
                                 const std::string& child_frame)
{
  nav_msgs::Odometry msg;
  msg.header.stamp = ros::Time(std::max(0.0, state.stamp_s));
  msg.header.frame_id = odom_frame;
  msg.child_frame_id = child_frame;
  msg.pose.pose = toPoseMsg(state.pose);
  setCovariance(&msg.pose.covariance, state.covariance);
  msg.twist.twist.linear.x = state.velocity(0);
  msg.twist.twist.linear.y = state.velocity(1);
  msg.twist.twist.angular.z = state.velocity(2);
  setCovariance(&msg.twist.covariance, state.velocity_covariance);
  return msg;
}

nav_msgs::Path toPathMsg(const std::vector<StampedPose2>& poses, const std::string& frame,
                         const ros::Time& stamp)
{
  nav_msgs::Path path;
  path.header.stamp = stamp;
  path.header.frame_id = frame;
  for (const StampedPose2& entry : poses)
    path.poses.push_back(toPoseStampedMsg(entry.pose, entry.stamp_s, frame));
  return path;
}

diagnostic_msgs::DiagnosticStatus toDiagnosticStatus(const SessionStatusReport& report,
                                                     const std::string& name,
                                                     const std::string& hardware_id)
{
  diagnostic_msgs::DiagnosticStatus status;
  status.name = name;
  status.hardware_id = hardware_id;
  status.level =
      report.level == SessionStatusReport::Level::kError  ? diagnostic_msgs::DiagnosticStatus::ERROR
      : report.level == SessionStatusReport::Level::kWarn ? diagnostic_msgs::DiagnosticStatus::WARN
                                                          : diagnostic_msgs::DiagnosticStatus::OK;
  status.message = report.message;
  for (const auto& [key, value] : report.values) {
    diagnostic_msgs::KeyValue entry;
    entry.key = key;
    entry.value = value;
    status.values.push_back(entry);
  }
  return status;
}

visualization_msgs::Marker toGuidanceMarker(const AssistantMarker& state,
                                            const GuidanceMarkerStyle& style,
                                            const ros::Time& stamp)
{
  visualization_msgs::Marker marker;
  marker.header.stamp = stamp;
  marker.header.frame_id = style.frame;
  marker.ns = "odometry_calibration";
  marker.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  marker.action = visualization_msgs::Marker::ADD;
  marker.pose.position.z = style.height_m;
  marker.pose.orientation.w = 1.0;
  marker.scale.z = style.text_height_m;
  marker.color.a = 1.0;
  marker.color.r = state.alarm ? 0.85f : (state.ready ? 0.0f : 0.8f);
  marker.color.g = state.alarm ? 0.0f : (state.ready ? 0.5f : 0.4f);
  marker.text = state.text;
  return marker;
}

}  // namespace ros_conversions
}  // namespace odometry_calibration
