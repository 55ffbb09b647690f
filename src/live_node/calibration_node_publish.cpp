// The live node's outputs: what the session reports, as messages (odometry, tf, paths, pairs,
// /diagnostics, the guidance marker, the health statistic).
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <std_msgs/Float64.h>

#include "odometry_calibration/live_node/calibration_node.h"
#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/report_messages.h"
#include "odometry_calibration/ros/session_messages.h"

namespace odometry_calibration {

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
  const nav_msgs::Odometry msg = ros_conversions::toOdometryMsg(state, options_.odom_frame, child);
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
  using ros_conversions::toPathMsg;
  const OdometryPaths paths = session_->paths();
  const ros::Time now = ros::Time::now();
  if (session_->hasNominalOdometry())
    nominal_path_publisher_.publish(toPathMsg(paths.nominal, options_.odom_frame, now));
  corrected_path_publisher_.publish(toPathMsg(paths.corrected, options_.odom_frame, now));
  scan_path_publisher_.publish(toPathMsg(paths.scan_matched, options_.odom_frame, now));
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
  const std::string node = ros::this_node::getName() + ": ";
  for (const SessionStatusReport& report : reports) {
    array->status.push_back(
        ros_conversions::toDiagnosticStatus(report, node + report.name + suffix, hardware_id));
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
  const ros_conversions::GuidanceMarkerStyle style{options_.base_frame, options_.marker_height_m,
                                                   options_.marker_text_height_m};
  guidance_marker_publisher_.publish(
      ros_conversions::toGuidanceMarker(state, style, ros::Time::now()));
}

}  // namespace odometry_calibration
