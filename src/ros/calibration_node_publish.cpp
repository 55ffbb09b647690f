// The live node's outputs: what the session reports, as messages (odometry, tf, paths, pairs,
// /diagnostics, the guidance marker, the health statistic).
#include <algorithm>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Path.h>
#include <std_msgs/Float64.h>
#include <visualization_msgs/Marker.h>

#include "odometry_calibration/ros/calibration_node.h"
#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/report_messages.h"

namespace odometry_calibration {
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

nav_msgs::Path toPathMsg(const std::vector<StampedPose2>& poses, const std::string& frame)
{
  nav_msgs::Path path;
  path.header.stamp = ros::Time::now();
  path.header.frame_id = frame;
  for (const StampedPose2& entry : poses)
    path.poses.push_back(ros_conversions::toPoseStampedMsg(entry.pose, entry.stamp_s, frame));
  return path;
}

}  // namespace

SessionListener CalibrationNode::listener(std::size_t k)
{
  SessionListener listener;
  listener.pair = [this, k](const MotionPair& pair) { publishPair(k, pair); };
  listener.odometry = [this](const OdometryState& state) { publishOdometry(state); };
  listener.sensor_pose = [this, k](const std::optional<Pose2>& T_base_sensor,
                                   const std::string& frame) {
    publishSensorPose(k, T_base_sensor, frame);
  };
  return listener;
}

void CalibrationNode::publishPair(std::size_t k, const MotionPair& pair)
{
  pairs_publisher_.publish(
      ros_conversions::toPairMsg(pair, jointLayout(config_), sensor_frames_.at(k)));
}

void CalibrationNode::publishOdometry(const OdometryState& state)
{
  const std::string child = state.tracks_base ? options_.base_frame : sensor_frames_.front();
  nav_msgs::Odometry msg;
  msg.header.stamp = ros::Time(std::max(0.0, state.stamp_s));
  msg.header.frame_id = options_.odom_frame;
  msg.child_frame_id = child;
  msg.pose.pose = ros_conversions::toPoseMsg(state.pose);
  setCovariance(&msg.pose.covariance, state.covariance);
  msg.twist.twist.linear.x = state.velocity(0);
  msg.twist.twist.linear.y = state.velocity(1);
  msg.twist.twist.angular.z = state.velocity(2);
  setCovariance(&msg.twist.covariance, state.velocity_covariance);
  odom_publisher_.publish(msg);
  if (options_.publish_odom_tf) {
    geometry_msgs::TransformStamped transform;
    transform.header = msg.header;
    transform.child_frame_id = child;
    transform.transform = ros_conversions::toTransformMsg(state.pose);
    tf_broadcaster_.sendTransform(transform);
  }
}

void CalibrationNode::publishSensorPose(std::size_t k, const std::optional<Pose2>& T_base_sensor,
                                        const std::string& frame)
{
  sensor_frames_.at(k) = frame;
  if (!options_.publish_extrinsic_tf || !T_base_sensor)
    return;
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = ros::Time::now();
  transform.header.frame_id = options_.base_frame;
  transform.child_frame_id = frame;
  transform.transform = ros_conversions::toTransformMsg(*T_base_sensor);
  static_broadcaster_.sendTransform(transform);
}

void CalibrationNode::onTimer(const ros::WallTimerEvent&)
{
  // Input rates over ROS time: a replay at twice the speed (use_sim_time) shows the recorded
  // rates, and a stopped simulated clock (the replay's end) no time at all.
  const ros::Time now = ros::Time::now();
  const double period_s = last_diagnostics_time_.isZero()
                              ? options_.diagnostics_period_s
                              : std::max(0.0, (now - last_diagnostics_time_).toSec());
  last_diagnostics_time_ = now;
  sessions_->tick();
  publishDiagnostics(period_s);
  publishAssistant();
  publishPaths();
}

void CalibrationNode::publishPaths()
{
  const OdometryPaths paths = session_->paths();
  if (session_->hasNominalOdometry())
    nominal_path_publisher_.publish(toPathMsg(paths.nominal, options_.odom_frame));
  corrected_path_publisher_.publish(toPathMsg(paths.corrected, options_.odom_frame));
  scan_path_publisher_.publish(toPathMsg(paths.scan_matched, options_.odom_frame));
}

void CalibrationNode::publishDiagnostics(double period_s)
{
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  // With several sources, each source's statuses are named with its topic (a silent laser or
  // one whose pairs are all rejected shows as that laser's).
  const bool several = sessions_->sourceCount() > 1;
  for (std::size_t k = 0; k < sessions_->sourceCount(); ++k) {
    CalibrationSession& session = sessions_->source(k);
    const std::string suffix = several ? " (" + sessions_->sourceConfig(k).topic + ")" : "";
    appendStatuses(session.statusReports(period_s), session.sensorFrame(), suffix, &array);
  }
  // The joint calibration's health monitor (several sources): names the laser that moved.
  appendStatuses(sessions_->jointStatusReports(), options_.base_frame, "", &array);
  diagnostics_publisher_.publish(array);
}

void CalibrationNode::appendStatuses(const std::vector<SessionStatusReport>& reports,
                                     const std::string& hardware_id, const std::string& suffix,
                                     diagnostic_msgs::DiagnosticArray* array) const
{
  for (const SessionStatusReport& report : reports) {
    diagnostic_msgs::DiagnosticStatus status;
    status.name = ros::this_node::getName() + ": " + report.name + suffix;
    status.hardware_id = hardware_id;
    status.level = report.level == SessionStatusReport::Level::kError
                       ? diagnostic_msgs::DiagnosticStatus::ERROR
                   : report.level == SessionStatusReport::Level::kWarn
                       ? diagnostic_msgs::DiagnosticStatus::WARN
                       : diagnostic_msgs::DiagnosticStatus::OK;
    status.message = report.message;
    for (const auto& [key, value] : report.values) {
      diagnostic_msgs::KeyValue entry;
      entry.key = key;
      entry.value = value;
      status.values.push_back(entry);
    }
    array->status.push_back(status);
  }
}

void CalibrationNode::publishAssistant()
{
  if (const std::optional<double> statistic = sessions_->healthStatistic()) {
    std_msgs::Float64 message;
    message.data = *statistic;
    health_statistic_publisher_.publish(message);
  }
  const AssistantMarker state = sessions_->assistantMarker();
  if (state.text.empty())
    return;
  visualization_msgs::Marker marker;
  marker.header.stamp = ros::Time::now();
  marker.header.frame_id = options_.base_frame;
  marker.ns = "odometry_calibration";
  marker.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  marker.action = visualization_msgs::Marker::ADD;
  marker.pose.position.z = options_.marker_height_m;
  marker.pose.orientation.w = 1.0;
  marker.scale.z = options_.marker_text_height_m;
  // Dark colours (rviz/calibration.rviz has a white background): red for a stale calibration,
  // green when ready to fit, orange while collecting.
  marker.color.a = 1.0;
  marker.color.r = state.alarm ? 0.85f : (state.ready ? 0.0f : 0.8f);
  marker.color.g = state.alarm ? 0.0f : (state.ready ? 0.5f : 0.4f);
  marker.text = state.text;
  guidance_marker_publisher_.publish(marker);
}

}  // namespace odometry_calibration
