// What the calibration session reports, as ROS messages: its log lines (rosout), its odometry state
// (nav_msgs/Odometry), its paths (nav_msgs/Path), its statuses (diagnostic_msgs/DiagnosticStatus)
// and the live assistant's text (a visualization_msgs/Marker for rviz). The live node publishes
// them.
#pragma once

#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/time.h>
#include <visualization_msgs/Marker.h>

#include "odometry_calibration/session/session_assistant.h"
#include "odometry_calibration/session/session_messages.h"
#include "odometry_calibration/session/session_odometry.h"

namespace odometry_calibration {
namespace ros_conversions {

/// The session's log line on ROS's log: ROS_INFO, ROS_WARN or ROS_ERROR by `level`.
void logToRos(SessionLogLevel level, const std::string& text);

/// `state` in `odom_frame`, its pose that of `child_frame` (the base, or the sensor when the
/// state does not track the base). (x, y, yaw) covariances go into ROS's 6x6 (x y z roll pitch
/// yaw) rows 0, 1, 5; z, roll and pitch, not estimated, get a variance of 1e6.
nav_msgs::Odometry toOdometryMsg(const OdometryState& state, const std::string& odom_frame,
                                 const std::string& child_frame);

/// `poses` as a path in `frame`, stamped `stamp`.
nav_msgs::Path toPathMsg(const std::vector<StampedPose2>& poses, const std::string& frame,
                         const ros::Time& stamp);

/// One status named `name` (the node's name, the report's, a suffix) for `hardware_id`.
diagnostic_msgs::DiagnosticStatus toDiagnosticStatus(const SessionStatusReport& report,
                                                     const std::string& name,
                                                     const std::string& hardware_id);

/// Where and how the assistant's text is drawn above the base.
struct GuidanceMarkerStyle
{
  std::string frame;            ///< the base's frame
  double height_m = 1.0;        ///< the text above the frame's origin [m]
  double text_height_m = 0.25;  ///< a letter's height [m]
};

/// The assistant's text facing the viewer, in dark colours for rviz's white background
/// (rviz/calibration.rviz): red for a stale calibration, green when ready to fit, orange
/// while collecting.
visualization_msgs::Marker toGuidanceMarker(const AssistantMarker& state,
                                            const GuidanceMarkerStyle& style,
                                            const ros::Time& stamp);

}  // namespace ros_conversions
}  // namespace odometry_calibration
