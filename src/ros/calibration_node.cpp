#include "odometry_calibration/ros/calibration_node.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/saved_calibration_score.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/point_cloud_conversion.h"
#include "odometry_calibration/ros/report_messages.h"
#include "odometry_calibration/scan/cloud_to_scan.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Scan-matched and odometry paths keep this many seconds of corrected sensor poses to bridge
/// rejected keyframe intervals.
constexpr double kRecentPoseHistoryS = 60.0;

/// Assumed per-keyframe-interval covariance of the uncalibrated (nominal) odometry: 1 cm, 1 cm,
/// 0.01 rad [m^2, m^2, rad^2].
const Eigen::Matrix3d kNominalWindowCovariance = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();

void appendToPath(nav_msgs::Path* path, const geometry_msgs::PoseStamped& pose, int max_poses)
{
  path->poses.push_back(pose);
  if (static_cast<int>(path->poses.size()) > max_poses)
    path->poses.erase(path->poses.begin(), path->poses.begin() + (path->poses.size() - max_poses));
}

}  // namespace

CalibrationNode::CalibrationNode(ros::NodeHandle handle, ros::NodeHandle private_handle)
    : handle_(handle),
      private_handle_(private_handle),
      options_(readNodeOptions(private_handle)),
      config_text_(readTextFile(options_.config_path, "the configuration")),
      config_(parseCalibrationConfig(config_text_, options_.config_path)),
      channels_(encoderChannels(config_)),
      odometry_decoder_(channels_)
{
  if (options_.output_directory.empty())
    options_.output_directory = config_.output_directory;
  model_interval_s_ = config_.collector.keyframe_interval_s;
  fs::create_directories(options_.output_directory);
  started_ = ros::WallTime::now();

  // The last saved calibration: its model drives the corrected odometry, its time offset the
  // pairing, its extrinsic the static transform.
  const std::string result_path = options_.output_directory + "/result.yaml";
  if (options_.load_saved_calibration && fs::exists(result_path)) {
    try {
      const CalibrationResult saved = readCalibrationResult(result_path);
      // Another robot's (or configuration's) result: its joints (when recorded) must be these,
      // and its model must take them.
      requireCalibrationJoints(saved.joints, jointLayout(config_).names, "the configuration");
      const auto joints = static_cast<Eigen::Index>(channels_.size());
      saved.model->predict(
          {{0.0, Eigen::VectorXd::Zero(joints)}, {0.1, Eigen::VectorXd::Zero(joints)}});
      active_model_ = saved.model;
      active_model_origin_ = "saved " + result_path;
      if (saved.has_extrinsic)
        T_base_sensor_ = saved.T_base_sensor;
      config_.collector.time_offset_s = saved.time_offset_s;
      if (saved.fit_interval_s > 0.0)
        model_interval_s_ = saved.fit_interval_s;
      ROS_INFO("loaded the saved calibration %s (model %s, time offset %.3f s)",
               result_path.c_str(), saved.model->name().c_str(), saved.time_offset_s);
    } catch (const std::exception& error) {
      ROS_ERROR("cannot use the saved calibration (%s): starting from the nominal model",
                error.what());
    }
  }

  collector_ =
      std::make_unique<PairCollector>(channels_, config_.collector, priorPredictor(config_));
  std::vector<double> other_intervals;
  for (const double interval : config_.fit_intervals_s) {
    if (std::abs(interval - config_.collector.keyframe_interval_s) > 1e-9)
      other_intervals.push_back(interval);
  }
  if (!other_intervals.empty()) {
    candidates_ = std::make_unique<CandidateCollectors>(channels_, config_.collector,
                                                        priorPredictor(config_), other_intervals);
  }
  const std::string pairs_path = options_.output_directory + "/pairs.csv";
  if (!options_.resume_pairs && fs::exists(pairs_path))
    archivePairsFile("~resume_pairs is false");
  try {
    appender_ = std::make_unique<PairsCsvAppender>(pairs_path, jointLayout(config_));
  } catch (const std::runtime_error& error) {
    // Another robot's or configuration's pairs: keep them aside, never delete them.
    ROS_WARN("%s", error.what());
    archivePairsFile("its joints differ from the configuration's");
    appender_ = std::make_unique<PairsCsvAppender>(pairs_path, jointLayout(config_));
  }
  pairs_ = appender_->existing();
  pairs_resumed_ = pairs_.size();
  if (appender_->dropped_partial_line())
    ROS_WARN("%s: dropped a last line cut off by a crash", pairs_path.c_str());
  if (!pairs_.empty())
    ROS_INFO("resumed %zu pairs from %s", pairs_.size(), pairs_path.c_str());

  // The nominal robot (the prior model at its start values) drives the nominal odometry, and
  // the corrected one until a calibration is fitted or loaded.
  if (std::shared_ptr<MotionModel> nominal = priorModel(config_)) {
    nominal_odometry_ = std::make_unique<OdometryIntegrator>(nominal, priorSensorPose(config_),
                                                             config_.collector.keyframe_interval_s);
    if (!active_model_) {
      active_model_ = nominal;
      active_model_origin_ = "nominal " + nominal->name() + " (configuration's start values)";
      T_base_sensor_.reset();
    }
  }
  if (active_model_) {
    const bool nominal = !T_base_sensor_ && active_model_origin_.rfind("nominal", 0) == 0;
    corrected_odometry_ = std::make_unique<OdometryIntegrator>(
        active_model_, nominal ? priorSensorPose(config_) : T_base_sensor_,
        nominal ? config_.collector.keyframe_interval_s : model_interval_s_);
    // The nominal robot reports no uncertainty of its own: assume 1 cm and 0.01 rad per
    // keyframe interval until a fit replaces it with the residual spread.
    if (nominal)
      corrected_odometry_->setWindowCovarianceFloor(kNominalWindowCovariance);
  } else {
    ROS_WARN(
        "no odometry until the first ~calibrate: prior_model is 'none' and there is no "
        "saved calibration");
  }

  setUpAssistant();  // issue 18: guidance and health monitor

  for (nav_msgs::Path* path : {&nominal_path_, &corrected_path_, &scan_matched_path_})
    path->header.frame_id = options_.odom_frame;

  joint_health_.topic = handle_.resolveName(config_.joint_state_topic);
  joint_subscriber_ =
      handle_.subscribe(config_.joint_state_topic, 2000, &CalibrationNode::onJointState, this,
                        ros::TransportHints().tcpNoDelay());
  switch (config_.ego_motion) {
    case EgoMotionSource::kScan:
      ego_health_.topic = handle_.resolveName(config_.scan_topic);
      ego_subscriber_ = handle_.subscribe(config_.scan_topic, 400, &CalibrationNode::onScan, this,
                                          ros::TransportHints().tcpNoDelay());
      break;
    case EgoMotionSource::kCloud:
      ego_health_.topic = handle_.resolveName(config_.ego_motion_topic);
      ego_subscriber_ = handle_.subscribe(config_.ego_motion_topic, 50, &CalibrationNode::onCloud,
                                          this, ros::TransportHints().tcpNoDelay());
      break;
    case EgoMotionSource::kOdometry:
      ego_health_.topic = handle_.resolveName(config_.ego_motion_topic);
      ego_subscriber_ =
          handle_.subscribe(config_.ego_motion_topic, 400, &CalibrationNode::onOdometry, this,
                            ros::TransportHints().tcpNoDelay());
      break;
    case EgoMotionSource::kPose:
      ego_health_.topic = handle_.resolveName(config_.ego_motion_topic);
      ego_subscriber_ = handle_.subscribe(config_.ego_motion_topic, 400, &CalibrationNode::onPose,
                                          this, ros::TransportHints().tcpNoDelay());
      break;
  }

  odom_publisher_ = private_handle_.advertise<nav_msgs::Odometry>("odom", 50);
  nominal_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/nominal", 1, true);
  corrected_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/corrected", 1, true);
  scan_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/scan_matched", 1, true);
  pairs_publisher_ = private_handle_.advertise<odometry_calibration::CalibrationPair>("pairs", 100);
  report_publisher_ =
      private_handle_.advertise<odometry_calibration::CalibrationReport>("report", 1, true);
  diagnostics_publisher_ = handle_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  publishExtrinsic();

  // Fits can take seconds: services run on their own thread so the inputs keep flowing.
  ros::NodeHandle service_handle(private_handle_);
  service_handle.setCallbackQueue(&service_queue_);
  calibrate_service_ =
      service_handle.advertiseService("calibrate", &CalibrationNode::onCalibrate, this);
  save_service_ = service_handle.advertiseService("save", &CalibrationNode::onSave, this);
  reset_service_ = service_handle.advertiseService("reset", &CalibrationNode::onReset, this);
  timer_ = service_handle.createWallTimer(ros::WallDuration(options_.diagnostics_period_s),
                                          &CalibrationNode::onTimer, this);
  service_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &service_queue_);
  service_spinner_->start();
  ROS_INFO(
      "collecting pairs: JointState on %s, ego-motion on %s, keyframes every %.2f s, "
      "time offset %.3f s; output in %s",
      joint_health_.topic.c_str(), ego_health_.topic.c_str(), config_.collector.keyframe_interval_s,
      config_.collector.time_offset_s, options_.output_directory.c_str());
}

CalibrationNode::~CalibrationNode()
{
  // Stop what runs on the service queue before its members go.
  timer_.stop();
  if (service_spinner_)
    service_spinner_->stop();
  calibrate_service_.shutdown();
  save_service_.shutdown();
  reset_service_.shutdown();
  timer_ = ros::WallTimer();
}

std::string CalibrationNode::sensorFrame() const
{
  if (!scan_frame_.empty())
    return scan_frame_;
  return options_.sensor_frame.empty() ? std::string("laser") : options_.sensor_frame;
}

// --- Inputs -------------------------------------------------------------------------------

void CalibrationNode::warnInput(const std::string& problem, const std::string& text)
{
  // Each problem at once, then at most every 5 s (the counts go on in /diagnostics).
  const std::string& key = problem;
  const ros::WallTime now = ros::WallTime::now();
  auto [entry, is_new] = input_warnings_.emplace(key, now);
  if (is_new || (now - entry->second).toSec() > 5.0) {
    entry->second = now;
    ROS_WARN("%s", text.c_str());
  }
}

void CalibrationNode::onJointState(const sensor_msgs::JointState::ConstPtr& message)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++joint_health_.messages;
  joint_health_.last_message = ros::WallTime::now();
  Eigen::VectorXd raw;
  try {
    raw = applySigns(config_, ros_conversions::rawJointPositions(*message, channels_));
  } catch (const std::invalid_argument& error) {
    ++bad_joint_states_;
    last_problem_ = "JointState skipped: " + std::string(error.what());
    warnInput(error.what(), "JointState on " + joint_health_.topic + " skipped (" +
                                std::to_string(bad_joint_states_) + " so far): " + error.what());
    return;
  }
  const double stamp_s = message->header.stamp.toSec();
  Eigen::VectorXd accepted;
  try {
    handleEvents(collector_->addEncoders(stamp_s, raw, &accepted), stamp_s);
    if (candidates_)
      candidates_->addEncoders(stamp_s, raw);
  } catch (const std::invalid_argument& error) {
    ++bad_joint_states_;
    last_problem_ = "JointState rejected: " + std::string(error.what());
    warnInput(error.what(), "JointState on " + joint_health_.topic + " rejected: " + error.what());
    return;
  }
  if (accepted.size() > 0) {  // empty for an encoder glitch: not motion
    recordEncoderHistory(stamp_s, accepted);
    integrateOdometry(stamp_s, accepted);
  }
}

void CalibrationNode::onScan(const sensor_msgs::LaserScan::ConstPtr& message)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++ego_health_.messages;
  ego_health_.last_message = ros::WallTime::now();
  if (!message->header.frame_id.empty() && message->header.frame_id != scan_frame_) {
    if (!scan_frame_.empty()) {
      ROS_WARN("the scans' frame changed from '%s' to '%s'", scan_frame_.c_str(),
               message->header.frame_id.c_str());
    }
    scan_frame_ = message->header.frame_id;
    publishExtrinsic();
  }
  const double stamp_s = message->header.stamp.toSec();
  try {
    const Scan scan = ros_conversions::fromLaserScanMsg(*message);
    const std::size_t usable = countUsableReadings(scan);
    if (static_cast<int>(usable) < config_.collector.plicp.min_points) {
      throw std::invalid_argument(
          "only " + std::to_string(usable) + " of " + std::to_string(scan.ranges_m.size()) +
          " ranges are usable (the rest NaN, inf or outside [range_min, range_max]); matching "
          "needs scan_matching.min_points = " +
          std::to_string(config_.collector.plicp.min_points));
    }
    handleEvents(collector_->addScan(stamp_s, scan), stamp_s);
    if (candidates_)
      candidates_->addScan(stamp_s, scan);
  } catch (const std::invalid_argument& error) {
    ++bad_scans_;
    last_problem_ = "LaserScan skipped: " + std::string(error.what());
    warnInput(error.what(), "LaserScan on " + ego_health_.topic + " skipped (" +
                                std::to_string(bad_scans_) + " so far): " + error.what());
  }
}

void CalibrationNode::onCloud(const sensor_msgs::PointCloud2::ConstPtr& message)
{
  // The conversion and filtering run before the lock: the encoders keep flowing meanwhile.
  const std::string& frame = message->header.frame_id;
  std::string problem;
  std::string time_problem;  // the cloud is used, without its per-point times
  Scan scan;
  try {
    const auto lidar = ros_conversions::fromPointCloud2Msg(*message, config_.cloud.point_times);
    scan = cloudToScan(lidar.cloud, lidar.has_times, config_.cloud);
    time_problem = lidar.time_problem;
  } catch (const std::invalid_argument& error) {
    problem = error.what();
  }
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++ego_health_.messages;
  ego_health_.last_message = ros::WallTime::now();
  if (frame.empty()) {
    problem = "PointCloud2 names no frame (header.frame_id is empty)";
  } else if (!cloud_frame_.empty() && frame != cloud_frame_) {
    problem = "PointCloud2 in frame '" + frame + "', not the sensor's frame '" + cloud_frame_ +
              "' (the first cloud's)";
  } else if (cloud_frame_.empty()) {
    cloud_frame_ = frame;
    scan_frame_ = frame;
    publishExtrinsic();
  }
  if (!problem.empty()) {
    ++bad_scans_;
    last_problem_ = "PointCloud2 skipped: " + problem;
    warnInput(problem, "PointCloud2 on " + ego_health_.topic + " skipped (" +
                           std::to_string(bad_scans_) + " so far): " + problem);
    return;
  }
  if (!time_problem.empty()) {
    ++clouds_without_times_;
    last_problem_ = "PointCloud2 " + time_problem;
    warnInput("per-point times ignored", "PointCloud2 on " + ego_health_.topic + ": " +
                                             time_problem + " (" +
                                             std::to_string(clouds_without_times_) + " so far)");
  }
  const double stamp_s = message->header.stamp.toSec();
  try {
    handleEvents(collector_->addScan(stamp_s, scan), stamp_s);
  } catch (const std::invalid_argument& error) {
    ++bad_scans_;
    last_problem_ = "PointCloud2 skipped: " + std::string(error.what());
    warnInput(error.what(), "PointCloud2 on " + ego_health_.topic + " skipped (" +
                                std::to_string(bad_scans_) + " so far): " + error.what());
  }
}

void CalibrationNode::onOdometry(const nav_msgs::Odometry::ConstPtr& message)
{
  onSensorPose(message->header.stamp.toSec(), message->pose.pose, message->child_frame_id);
}

void CalibrationNode::onPose(const geometry_msgs::PoseStamped::ConstPtr& message)
{
  onSensorPose(message->header.stamp.toSec(), message->pose, "");
}

void CalibrationNode::onSensorPose(double stamp_s, const geometry_msgs::Pose& pose,
                                   const std::string& frame)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++ego_health_.messages;
  ego_health_.last_message = ros::WallTime::now();
  if (!frame.empty() && frame != scan_frame_) {
    scan_frame_ = frame;
    publishExtrinsic();
  }
  const double sigma_m = config_.ego_motion_sigma_m, sigma_rad = config_.ego_motion_sigma_rad;
  const Eigen::Matrix3d covariance =
      Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  try {
    const Pose2 T_world_sensor = ros_conversions::fromPoseMsg(pose);
    handleEvents(collector_->addSensorPose(stamp_s, T_world_sensor, covariance), stamp_s);
    if (candidates_)
      candidates_->addSensorPose(stamp_s, T_world_sensor, covariance);
  } catch (const std::invalid_argument& error) {
    ++bad_scans_;
    last_problem_ = "sensor pose skipped: " + std::string(error.what());
    warnInput(error.what(), "pose on " + ego_health_.topic + " skipped: " + error.what());
  }
}

void CalibrationNode::handleEvents(const std::vector<CollectorEvent>& events, double stamp_s)
{
  for (const CollectorEvent& event : events) {
    switch (event.type) {
      case CollectorEvent::Type::kPair:
        pairs_.push_back(event.pair);
        ++pairs_unwritten_;
        writePendingPairs();
        pairs_publisher_.publish(
            ros_conversions::toPairMsg(event.pair, jointLayout(config_), sensorFrame()));
        addScanMatchedPose(event.pair);
        assistantAddPair(event.pair);
        break;
      case CollectorEvent::Type::kRestarted:
        ROS_WARN(
            "time went backwards at %.3f s (%s): keyframe pairing and odometry restarted, "
            "the %zu pairs collected are kept",
            stamp_s, event.reason.c_str(), pairs_.size());
        last_problem_ = "time went backwards: " + event.reason;
        restartOdometry();
        break;
      case CollectorEvent::Type::kGlitch:
        last_problem_ = event.reason;
        warnInput(event.reason.substr(0, event.reason.find(':')),
                  event.reason + " (counted on /diagnostics)");
        break;
      case CollectorEvent::Type::kRejected:
        // Each reason once as a warning; the counts are on /diagnostics.
        if (rejection_reasons_seen_.insert(event.reason).second) {
          ROS_WARN(
              "keyframe interval rejected (first time for this reason; counted on "
              "/diagnostics): %s",
              event.reason.c_str());
        }
        break;
      default:
        break;
    }
  }
}

// --- Odometry and paths ---------------------------------------------------------------------

void CalibrationNode::integrateOdometry(double encoder_stamp_s, const Eigen::VectorXd& raw)
{
  if (!(encoder_stamp_s > last_encoder_stamp_s_)) {
    if (encoder_stamp_s < last_encoder_stamp_s_)
      restartOdometry();  // the collector has reported (and restarted) already
    else
      return;  // a repeated stamp adds nothing
  }
  last_encoder_stamp_s_ = encoder_stamp_s;
  EncoderSample sample{encoder_stamp_s, odometry_decoder_.decode(raw)};
  // Published in the laser's clock: encoder time t_e shows the robot at laser time t_e - tau.
  const double stamp_s = encoder_stamp_s - config_.collector.time_offset_s;
  sample.stamp_s = stamp_s;
  try {
    if (nominal_odometry_)
      nominal_odometry_->add(sample);
    if (!corrected_odometry_)
      return;
    corrected_odometry_->add(sample);
  } catch (const std::exception& error) {
    ROS_WARN_THROTTLE(10.0, "odometry prediction failed: %s", error.what());
    return;
  }
  const OdometryIntegrator& odometry = *corrected_odometry_;
  const std::string child = odometry.tracksBase() ? options_.base_frame : sensorFrame();
  const Pose2 pose = odometry.pose();
  nav_msgs::Odometry msg;
  msg.header.stamp = ros::Time(std::max(0.0, stamp_s));
  msg.header.frame_id = options_.odom_frame;
  msg.child_frame_id = child;
  msg.pose.pose = ros_conversions::toPoseMsg(pose);
  const Eigen::Matrix3d covariance = odometry.covariance();
  const int index[3] = {0, 1, 5};  // x, y, yaw in ROS's 6x6 (x y z roll pitch yaw)
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      msg.pose.covariance[6 * index[r] + index[c]] = covariance(r, c);
  for (int i : {2, 3, 4})
    msg.pose.covariance[7 * i] = 1e6;  // z, roll, pitch: not estimated
  msg.twist.twist.linear.x = odometry.velocity()(0);
  msg.twist.twist.linear.y = odometry.velocity()(1);
  msg.twist.twist.angular.z = odometry.velocity()(2);
  // The velocity's spread: the odometry's growth over one window of its model, per second.
  const double interval_s = odometry.segmentLength();
  const Eigen::Matrix3d per_interval = odometry.windowCovariance() / (interval_s * interval_s);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      msg.twist.covariance[6 * index[r] + index[c]] = per_interval(r, c);
  for (int i : {2, 3, 4})
    msg.twist.covariance[7 * i] = 1e6;
  odom_publisher_.publish(msg);
  if (options_.publish_odom_tf) {
    geometry_msgs::TransformStamped transform;
    transform.header = msg.header;
    transform.child_frame_id = child;
    transform.transform = ros_conversions::toTransformMsg(pose);
    tf_broadcaster_.sendTransform(transform);
  }
  recent_sensor_poses_.emplace_back(stamp_s, odometry.sensorPose());
  if (recent_sensor_poses_.front().first < stamp_s - kRecentPoseHistoryS) {
    recent_sensor_poses_.erase(recent_sensor_poses_.begin(),
                               recent_sensor_poses_.begin() + recent_sensor_poses_.size() / 2);
  }
  if (stamp_s - last_path_stamp_s_ >= options_.path_spacing_s) {
    last_path_stamp_s_ = stamp_s;
    appendToPath(&corrected_path_,
                 ros_conversions::toPoseStampedMsg(pose, stamp_s, options_.odom_frame),
                 options_.path_max_poses);
    path_samples_.push_back(sample);
    if (static_cast<int>(path_samples_.size()) > options_.path_max_poses) {
      path_samples_.pop_front();
      path_samples_start_ = ros_conversions::fromPoseMsg(corrected_path_.poses.front().pose);
    }
    if (nominal_odometry_) {
      appendToPath(&nominal_path_,
                   ros_conversions::toPoseStampedMsg(nominal_odometry_->pose(), stamp_s,
                                                     options_.odom_frame),
                   options_.path_max_poses);
    }
  }
}

void CalibrationNode::restartOdometry()
{
  odometry_decoder_.reset();
  last_encoder_stamp_s_ = -1e300;
  last_path_stamp_s_ = -1e300;
  if (nominal_odometry_)
    nominal_odometry_->reset();
  if (corrected_odometry_)
    corrected_odometry_->reset();
  nominal_path_.poses.clear();
  corrected_path_.poses.clear();
  path_samples_.clear();
  path_samples_start_ = Pose2();
  scan_matched_path_.poses.clear();
  scan_matched_sensor_poses_.clear();
  recent_sensor_poses_.clear();
  scan_matched_end_s_.reset();
}

void CalibrationNode::addScanMatchedPose(const MotionPair& pair)
{
  // The chain of matched displacements; after a rejected interval it restarts from the
  // corrected odometry's sensor pose at the pair's start.
  Pose2 start;
  if (scan_matched_end_s_ && std::abs(*scan_matched_end_s_ - pair.start_stamp_s) < 1e-9 &&
      !scan_matched_sensor_poses_.empty()) {
    start = scan_matched_sensor_poses_.back().second;
  } else {
    const auto after = std::lower_bound(
        recent_sensor_poses_.begin(), recent_sensor_poses_.end(), pair.start_stamp_s,
        [](const std::pair<double, Pose2>& entry, double stamp) { return entry.first < stamp; });
    if (after != recent_sensor_poses_.end())
      start = after->second;
    else if (!recent_sensor_poses_.empty())
      start = recent_sensor_poses_.back().second;
    scan_matched_sensor_poses_.emplace_back(pair.start_stamp_s, start);
  }
  scan_matched_sensor_poses_.emplace_back(pair.end_stamp_s, start * pair.sensor_motion);
  scan_matched_end_s_ = pair.end_stamp_s;
  if (static_cast<int>(scan_matched_sensor_poses_.size()) > options_.path_max_poses) {
    scan_matched_sensor_poses_.erase(scan_matched_sensor_poses_.begin());
  }
}

void CalibrationNode::publishPaths()
{
  const ros::Time now = ros::Time::now();
  for (nav_msgs::Path* path : {&nominal_path_, &corrected_path_, &scan_matched_path_})
    path->header.stamp = now;
  // The scan-matched sensor poses drawn as base_link poses through the current extrinsic (or
  // the configured one), so the three paths overlay.
  const Pose2 T_sensor_base =
      (T_base_sensor_ ? *T_base_sensor_ : priorSensorPose(config_).value_or(Pose2())).inverse();
  scan_matched_path_.poses.clear();
  for (const auto& [stamp_s, T_odom_sensor] : scan_matched_sensor_poses_) {
    scan_matched_path_.poses.push_back(ros_conversions::toPoseStampedMsg(
        T_odom_sensor * T_sensor_base, stamp_s, options_.odom_frame));
  }
  if (nominal_odometry_)
    nominal_path_publisher_.publish(nominal_path_);
  corrected_path_publisher_.publish(corrected_path_);
  scan_path_publisher_.publish(scan_matched_path_);
}

void CalibrationNode::publishExtrinsic()
{
  if (!options_.publish_extrinsic_tf || !T_base_sensor_)
    return;
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = ros::Time::now();
  transform.header.frame_id = options_.base_frame;
  transform.child_frame_id = sensorFrame();
  transform.transform = ros_conversions::toTransformMsg(*T_base_sensor_);
  static_broadcaster_.sendTransform(transform);
}

}  // namespace odometry_calibration
