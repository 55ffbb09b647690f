// The live calibration node (README, "The live node"): an adapter around the
// ROS-free calibration session (session/joint_calibration_session.h: one CalibrationSession per
// ego-motion source). JointState and LaserScan (or another ego-motion topic; with
// ego_motion.sources every source's topic) are converted and handed to the session; its pairs,
// odometry, sensor poses (base -> each sensor's frame), paths, statuses and assistant are
// published; ~calibrate (with several sources: the joint fit), ~save and ~reset call the
// session. Every decision is the session's, so calibrate_bag makes the same ones.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/ros/message_adapter.h"
#include "odometry_calibration/session/joint_calibration_session.h"

namespace odometry_calibration {

/// The node's own parameters (private namespace); the calibration itself is the YAML file.
struct NodeOptions
{
  std::string config_path;               ///< ~config: the calibration YAML (required)
  std::string output_directory;          ///< ~output_directory [config's output_directory]
  std::string odom_frame = "odom";       ///< ~odom_frame
  std::string base_frame = "base_link";  ///< ~base_frame
  std::string sensor_frame;              ///< ~sensor_frame: used until a scan names its frame
  bool publish_odom_tf = false;          ///< ~publish_odom_tf: odom -> base_link on tf
  bool publish_extrinsic_tf = true;      ///< ~publish_extrinsic_tf: base_link -> laser (static)
  double diagnostics_period_s = 1.0;     ///< ~diagnostics_period_s [s]
  double marker_height_m = 1.0;          ///< ~guidance_marker_height_m: text above base [m]
  double marker_text_height_m = 0.25;    ///< ~guidance_marker_text_m: height of a letter [m]
  /// ~holdout_fraction: the ~calibrate reply's held-out table on this last fraction of the
  /// pairs (CalibrationRequest::reply_holdout_fraction); 0: none.
  double holdout_fraction = 0.3;
  /// ~load_saved_calibration, ~resume_pairs, ~min_pairs, ~silent_topic_timeout_s, ~path_*,
  /// ~guidance*, ~health_*: the session's.
  SessionOptions session;
};

/// Reads and checks ~parameters. Throws std::invalid_argument naming a bad parameter.
NodeOptions readNodeOptions(const ros::NodeHandle& private_handle);

class CalibrationNode
{
public:
  /// Subscribes, advertises, starts the session (saved calibration, pairs file). Throws
  /// std::runtime_error with an actionable message when it cannot start (bad config).
  CalibrationNode(ros::NodeHandle handle, ros::NodeHandle private_handle);
  ~CalibrationNode();

  /// At exit: the inputs stop, the pairs not yet in the pairs file are written a last time;
  /// returns how many still could not be (said on the log with the file's problem).
  std::size_t finish();

private:
  void subscribe();
  void advertise();
  // Subscriptions to message events: the session checks who published each message
  // (input_publishers.h).
  /// wheels.source ticks: joint `wheel`'s topic of wheels.message_type.
  void subscribeWheelTicks(std::size_t wheel);
  // Source `k`'s messages (ego_motion.sources order; 0 with one source).
  void subscribeSource(std::size_t k);
  void onTimer(const ros::WallTimerEvent& event);
  bool onCalibrate(Calibrate::Request& request, Calibrate::Response& response);
  bool onSave(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);

  // Publishing what the session reports (calibration_node_publish.cpp).
  /// Source `k`'s listener.
  SessionListener listener(std::size_t k);
  void publishPair(std::size_t k, const MotionPair& pair);
  void publishOdometry(const OdometryState& state);
  /// Re-sends base -> source k's sensor (with ~publish_extrinsic_tf and a known pose).
  void publishSensorPose(std::size_t k, const std::optional<Pose2>& T_base_sensor,
                         const std::string& frame);
  void publishPaths();
  void publishDiagnostics(double period_s);
  /// `reports` as statuses named "<node>: <name><suffix>" into `array`.
  void appendStatuses(const std::vector<SessionStatusReport>& reports,
                      const std::string& hardware_id, const std::string& suffix,
                      diagnostic_msgs::DiagnosticArray* array) const;
  void publishAssistant();

  /// Declared first, destroyed last: the services and the timer are registered on it.
  ros::CallbackQueue service_queue_;
  ros::NodeHandle handle_, private_handle_;
  NodeOptions options_;
  CalibrationConfig config_;
  std::unique_ptr<MessageAdapter> adapter_;  ///< messages into session inputs
  std::unique_ptr<JointCalibrationSession> sessions_;
  CalibrationSession* session_ = nullptr;  ///< source 0's: odometry, paths, assistant
  bool finished_ = false;                  ///< finish() ran
  std::size_t lost_pairs_ = 0;             ///< pairs finish() could not write
  /// Each source's sensor frame as its session last said (set and read in its callbacks).
  std::vector<std::string> sensor_frames_;

  ros::Subscriber joint_subscriber_;
  std::vector<ros::Subscriber>
      tick_subscribers_;  ///< wheels.topics: a tick topic per joint, or the base's odometry
  std::vector<ros::Subscriber> ego_subscribers_;  ///< one per source
  ros::Subscriber gyro_subscriber_;               ///< gyro.topic's sensor_msgs/Imu, when set
  ros::Publisher odom_publisher_, nominal_path_publisher_, corrected_path_publisher_,
      scan_path_publisher_, pairs_publisher_, report_publisher_, diagnostics_publisher_,
      guidance_marker_publisher_, health_statistic_publisher_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  ros::WallTimer timer_;
  ros::Time last_diagnostics_time_;  ///< ROS time of the last /diagnostics (zero before)
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  ros::ServiceServer calibrate_service_, save_service_, reset_service_;
};

}  // namespace odometry_calibration
