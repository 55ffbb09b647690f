// The live calibration node (DESIGN.md, "Interfaces users touch"): JointState and LaserScan (or
// another ego-motion topic) in, keyframe pairs through the core's PairCollector, a fit on the
// ~calibrate service, corrected odometry, the learned base -> laser transform, paths for rviz
// and diagnostics out. A thin layer: every computation is the core's.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/assistant/excitation_guidance.h"
#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/pairing/pair_collector.h"

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
  bool load_saved_calibration = true;    ///< ~load_saved_calibration: result.yaml on start
  bool resume_pairs = true;              ///< ~resume_pairs: continue the pairs file on start
  double silent_topic_timeout_s = 5.0;   ///< ~silent_topic_timeout_s [s]
  int min_pairs = 10;                    ///< ~min_pairs: fewer and ~calibrate refuses
  double path_spacing_s = 0.1;           ///< ~path_spacing_s: odometry path sampling [s]
  int path_max_poses = 20000;            ///< ~path_max_poses: oldest poses dropped beyond [-]
  double diagnostics_period_s = 1.0;     ///< ~diagnostics_period_s [s]
};

/// Reads and checks ~parameters. Throws std::invalid_argument naming a bad parameter.
NodeOptions readNodeOptions(const ros::NodeHandle& private_handle);

/// The live assistant's ~parameters (issue 18; calibration_node_assistant.cpp).
struct AssistantOptions
{
  bool guidance = true;                ///< ~guidance: excitation guidance for diff_drive / tricycle
  double marker_height_m = 1.0;        ///< ~guidance_marker_height_m: text above base_frame [m]
  double marker_text_height_m = 0.25;  ///< ~guidance_marker_text_m: height of a letter [m]
  ExcitationGuidanceOptions guidance_options;  ///< ~guidance_* and ~guidance_target_sigma/<name>
  bool health_monitor = true;           ///< ~health_monitor: watch a fitted or saved calibration
  HealthMonitorOptions health_options;  ///< ~health_*
};

struct CalibrationJobResult;

/// The ~calibrate reply's sentence on the time offset: the estimate with sigma, or why there is
/// none ("" when the configuration does not ask for it).
std::string timeOffsetSentence(const CalibrationConfig& config, const CalibrationJobResult& job,
                               bool no_history);

/// Reads and checks the assistant's ~parameters. Throws std::invalid_argument naming a bad one.
AssistantOptions readAssistantOptions(const ros::NodeHandle& private_handle);

class CalibrationNode
{
public:
  /// Subscribes, advertises, loads the saved calibration and the pairs file. Throws
  /// std::runtime_error with an actionable message when it cannot start (bad config).
  CalibrationNode(ros::NodeHandle handle, ros::NodeHandle private_handle);
  ~CalibrationNode();

private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& message);
  void onScan(const sensor_msgs::LaserScan::ConstPtr& message);
  /// A 3D lidar's cloud (ego_motion.source: cloud): turned into a scan (cloud_to_scan.h) and
  /// paired like a LaserScan; the first cloud's frame is the sensor's, a cloud in another (or
  /// none) is skipped and counted, as is one the conversion rejects.
  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& message);
  void onOdometry(const nav_msgs::Odometry::ConstPtr& message);
  void onPose(const geometry_msgs::PoseStamped::ConstPtr& message);
  void onSensorPose(double stamp_s, const geometry_msgs::Pose& pose, const std::string& frame);
  void onTimer(const ros::WallTimerEvent& event);
  /// A bad-input warning: each distinct problem at once, then at most every 5 s.
  void warnInput(const std::string& problem, const std::string& text);

  bool onCalibrate(Calibrate::Request& request, Calibrate::Response& response);
  bool onSave(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);

  // The following run with state_mutex_ held.
  void handleEvents(const std::vector<CollectorEvent>& events, double stamp_s);
  void integrateOdometry(double encoder_stamp_s, const Eigen::VectorXd& raw);
  void restartOdometry();
  void addScanMatchedPose(const MotionPair& pair);
  void publishExtrinsic();
  void publishPaths();
  void publishDiagnostics(double period_s);
  /// Appends the unwritten pairs to the pairs file (reopening it if needed); on failure keeps
  /// them in memory, says so once, and is called again with the next pair and every period.
  void writePendingPairs();
  void warnSilentTopics();
  /// Moves the pairs file aside (pairs-<time>.csv); returns the new name.
  std::string archivePairsFile(const std::string& why);
  std::string sensorFrame() const;

  // The live assistant (issue 18, calibration_node_assistant.cpp): excitation guidance while
  // collecting, a health monitor of the active calibration. With state_mutex_ held, except
  // setUpAssistant (constructor).
  void setUpAssistant();
  void assistantAddPair(const MotionPair& pair);
  /// Watches `model` from now on (a fitted or saved calibration).
  void startHealthMonitor(const std::shared_ptr<const MotionModel>& model);
  void resetAssistant();
  /// After a fit of the guidance's model: the guidance linearised at the fitted values.
  void recentreGuidance(const std::string& model, const ModelReport& report);
  /// Keeps the decoded encoder sample for the time-offset search (estimate_time_offset only;
  /// time going backwards starts the history again).
  void recordEncoderHistory(double stamp_s, const Eigen::VectorXd& accepted);
  /// Pairs from now on at `time_offset_s` (a changed offset restarts pairing and odometry).
  void applyTimeOffset(double time_offset_s);
  /// The guidance in one sentence for the ~calibrate reply ("" without guidance).
  std::string guidanceSummary() const;
  /// Adds the guidance's and the monitor's statuses; publishes the marker and the statistic.
  void publishAssistant(std::vector<diagnostic_msgs::DiagnosticStatus>& statuses);

  /// Declared first, destroyed last: the services and the timer are registered on it.
  ros::CallbackQueue service_queue_;
  ros::NodeHandle handle_, private_handle_;
  NodeOptions options_;
  std::string config_text_;
  CalibrationConfig config_;
  std::vector<EncoderChannelOptions> channels_;

  std::mutex state_mutex_;
  std::unique_ptr<PairCollector> collector_;
  /// Pairs at the other keyframes.fit_intervals_s, for ~calibrate's choice of the fit interval
  /// (none when the configuration lists no candidates).
  std::unique_ptr<CandidateCollectors> candidates_;
  /// Window of the active model's predictions [s]: the interval its pairs spanned.
  double model_interval_s_ = 0.5;
  std::unique_ptr<PairsCsvAppender> appender_;
  std::vector<MotionPair> pairs_;
  std::size_t pairs_resumed_ = 0;
  /// The last pairs_unwritten_ of pairs_ are not in the pairs file yet (a full or read-only
  /// disk): written by writePendingPairs() as soon as it can.
  std::size_t pairs_unwritten_ = 0;
  std::string pairs_file_problem_;  ///< why the pairs file cannot be written now (empty: it can)
  EncoderDecoder odometry_decoder_;
  double last_encoder_stamp_s_ = -1e300;
  std::unique_ptr<OdometryIntegrator> nominal_odometry_;
  std::unique_ptr<OdometryIntegrator> corrected_odometry_;
  std::shared_ptr<const MotionModel> active_model_;
  std::string active_model_origin_;  ///< "nominal", "saved result.yaml", "fit at ..."
  std::shared_ptr<const MotionModel> fitted_model_;  ///< last successful fit (for ~save)
  std::string fitted_result_yaml_;                   ///< its result.yaml text
  std::string fitted_controller_yaml_;  ///< its controller.yaml text (empty: no controller form)
  std::optional<Pose2> T_base_sensor_;  ///< learned (or saved) extrinsic
  std::string scan_frame_;              ///< from the scans' headers
  std::string cloud_frame_;             ///< the first cloud's frame (cloud source)
  nav_msgs::Path nominal_path_, corrected_path_, scan_matched_path_;
  std::vector<std::pair<double, Pose2>> scan_matched_sensor_poses_;
  double last_path_stamp_s_ = -1e300;
  /// Encoder samples at the corrected path's poses, to redraw it after a fit, and the path's
  /// pose at the first of them.
  std::deque<EncoderSample> path_samples_;
  Pose2 path_samples_start_;
  /// Recent corrected sensor poses (laser clock), to place the scan-matched path after a gap.
  std::vector<std::pair<double, Pose2>> recent_sensor_poses_;
  std::optional<double> scan_matched_end_s_;

  // Input health.
  struct TopicHealth
  {
    std::string topic;
    std::size_t messages = 0;
    std::size_t messages_at_last_tick = 0;
    ros::WallTime last_message;
    ros::WallTime last_warning;
  };
  TopicHealth joint_health_, ego_health_;
  std::size_t bad_joint_states_ = 0;
  std::size_t bad_scans_ = 0;
  std::size_t clouds_without_times_ = 0;  ///< clouds used without their per-point times
  std::string last_problem_;
  std::set<std::string> rejection_reasons_seen_;
  std::map<std::string, ros::WallTime> input_warnings_;
  ros::WallTime started_;

  ros::Subscriber joint_subscriber_, ego_subscriber_;
  ros::Publisher odom_publisher_, nominal_path_publisher_, corrected_path_publisher_,
      scan_path_publisher_, pairs_publisher_, report_publisher_, diagnostics_publisher_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  ros::WallTimer timer_;
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  ros::ServiceServer calibrate_service_, save_service_, reset_service_;

  AssistantOptions assistant_options_;
  std::unique_ptr<EncoderDecoder> history_decoder_;
  std::vector<EncoderSample> encoder_history_;  ///< encoder clock, as calibrate_bag's
  std::unique_ptr<ExcitationGuidance> guidance_;
  std::string guidance_model_;            ///< the model the guidance is for
  ModelFactoryOptions guidance_factory_;  ///< its options (joints resolved)
  std::unique_ptr<HealthMonitor> health_monitor_;
  std::string health_model_origin_;  ///< what the monitor watches
  ros::Publisher guidance_marker_publisher_, health_statistic_publisher_;
};

}  // namespace odometry_calibration
