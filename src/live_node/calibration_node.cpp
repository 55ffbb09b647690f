#include "odometry_calibration/live_node/calibration_node.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Path.h>
#include <std_msgs/Float64.h>
#include <visualization_msgs/Marker.h>

#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/ros/report_messages.h"
#include "odometry_calibration/ros/session_messages.h"
#include "odometry_calibration/ros/wheel_tick_messages.h"
#include "odometry_calibration/session/converted_input.h"

namespace odometry_calibration {
namespace {

/// Subscribes `callback` to `topic`'s full message events, which keep the connection header (the
/// publisher's name). roscpp's subscribe<M> with a callable converts it to a callback
/// of the bare message and rebuilds the event without a header ("unknown_publisher").
template <class M, class Callback>
ros::Subscriber subscribeEvents(ros::NodeHandle& handle, const std::string& topic,
                                uint32_t queue_size, const Callback& callback,
                                const ros::TransportHints& hints)
{
  using Event = const ros::MessageEvent<const M>&;
  return handle.subscribe<M, Event>(topic, queue_size, boost::function<void(Event)>(callback),
                                    ros::VoidConstPtr(), hints);
}

}  // namespace

CalibrationNode::CalibrationNode(ros::NodeHandle handle, ros::NodeHandle private_handle)
    : handle_(handle), private_handle_(private_handle), options_(readNodeOptions(private_handle))
{
  const std::string config_text = readTextFile(options_.config_path, "the configuration");
  config_ = parseCalibrationConfig(config_text, options_.config_path);
  adapter_ = std::make_unique<MessageAdapter>(config_);
  SessionOptions& session = options_.session;
  if (session.output_directory.empty())
    session.output_directory = config_.output_directory;
  session.source = "live node " + ros::this_node::getName();
  session.base_frame = options_.base_frame;
  session.default_sensor_frame = options_.sensor_frame.empty() ? "laser" : options_.sensor_frame;
  const bool scan = config_.ego_motion == EgoMotionSource::kScan;
  // Ticks and the base's odometry come on wheels.topics, JointState on joint_state_topic.
  const bool wheel_topics = !config_.wheels.topics.empty();
  session.topics = {
      handle_.resolveName(wheel_topics ? config_.wheels.topics.front() : config_.joint_state_topic),
      handle_.resolveName(scan ? config_.scan_topic : config_.ego_motion_topic)};
  session.wall_clock = [] { return ros::WallTime::now().toSec(); };
  session.log = ros_conversions::logToRos;
  advertise();  // before the session: it publishes from its first moment
  sensor_frames_.assign(std::max<std::size_t>(1, config_.ego_motion_sources.size()),
                        session.default_sensor_frame);
  sessions_ =
      std::make_unique<JointCalibrationSession>(config_, config_text, options_.config_path, session,
                                                [this](std::size_t k) { return listener(k); });
  session_ = &sessions_->source(0);
  for (std::size_t k = 0; k < sessions_->sourceCount(); ++k)
    publishSensorPose(k, sessions_->source(k).sensorPose(), sessions_->source(k).sensorFrame());
  subscribe();
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
  ROS_INFO("%s", sessions_->startSummary().c_str());
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
  finish();
}

std::size_t CalibrationNode::finish()
{
  joint_subscriber_.shutdown();
  for (ros::Subscriber& subscriber : tick_subscribers_)
    subscriber.shutdown();
  for (ros::Subscriber& subscriber : ego_subscribers_)
    subscriber.shutdown();
  if (finished_)
    return lost_pairs_;
  finished_ = true;
  lost_pairs_ = sessions_->writePendingPairs();
  if (lost_pairs_ > 0) {
    ROS_ERROR(
        "%zu pairs were lost: never written to the pairs file in %s (the disk did not take "
        "them)",
        lost_pairs_, options_.session.output_directory.c_str());
  }
  return lost_pairs_;
}

void CalibrationNode::advertise()
{
  odom_publisher_ = private_handle_.advertise<nav_msgs::Odometry>("odom", 50);
  nominal_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/nominal", 1, true);
  corrected_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/corrected", 1, true);
  scan_path_publisher_ = private_handle_.advertise<nav_msgs::Path>("path/scan_matched", 1, true);
  pairs_publisher_ = private_handle_.advertise<odometry_calibration::CalibrationPair>("pairs", 100);
  report_publisher_ =
      private_handle_.advertise<odometry_calibration::CalibrationReport>("report", 1, true);
  diagnostics_publisher_ = handle_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  guidance_marker_publisher_ =
      private_handle_.advertise<visualization_msgs::Marker>("guidance_marker", 1, true);
  health_statistic_publisher_ =
      private_handle_.advertise<std_msgs::Float64>("health_statistic", 10);
}

void CalibrationNode::subscribe()
{
  const auto hints = ros::TransportHints().tcpNoDelay();
  if (config_.wheels.source == WheelSource::kTicks) {
    for (std::size_t j = 0; j < config_.wheels.topics.size(); ++j)
      subscribeWheelTicks(j);
  } else if (config_.wheels.source == WheelSource::kOdometry) {
    tick_subscribers_.push_back(subscribeEvents<nav_msgs::Odometry>(
        handle_, config_.wheels.topics.front(), 2000,
        [this](const ros::MessageEvent<const nav_msgs::Odometry>& event) {
          feedInput(*sessions_,
                    adapter_->convertBaseOdometry(*event.getMessage(), event.getPublisherName()));
        },
        hints));
  } else {
    joint_subscriber_ = subscribeEvents<sensor_msgs::JointState>(
        handle_, config_.joint_state_topic, 2000,
        [this](const ros::MessageEvent<const sensor_msgs::JointState>& event) {
          feedInput(*sessions_,
                    adapter_->convert(*event.getConstMessage(), event.getPublisherName()));
        },
        hints);
  }
  for (std::size_t k = 0; k < sessions_->sourceCount(); ++k)
    subscribeSource(k);
  if (!config_.gyro.topic.empty()) {  // 100-1000 Hz: a queue of two seconds or more
    gyro_subscriber_ = subscribeEvents<sensor_msgs::Imu>(
        handle_, config_.gyro.topic, 2000,
        [this](const ros::MessageEvent<const sensor_msgs::Imu>& event) {
          feedInput(*sessions_,
                    adapter_->convert(*event.getConstMessage(), event.getPublisherName()));
        },
        hints);
  }
}

void CalibrationNode::subscribeWheelTicks(std::size_t wheel)
{
  // The messages carry no stamp: each is taken at its receive time (the clock's, /clock's when
  // a bag is played with use_sim_time).
  const auto hints = ros::TransportHints().tcpNoDelay();
  tick_subscribers_.push_back(visitWheelTickType(config_.wheels.message_type, [&](auto message) {
    using M = decltype(message);
    return subscribeEvents<M>(
        handle_, config_.wheels.topics[wheel], 2000,
        [this, wheel](const ros::MessageEvent<const M>& event) {
          feedInput(*sessions_, adapter_->convertWheelTick(
                                    static_cast<double>(event.getMessage()->data), wheel,
                                    event.getReceiptTime().toSec(), event.getPublisherName()));
        },
        hints);
  }));
}

void CalibrationNode::subscribeSource(std::size_t k)
{
  // Each source's callback carries its index: its messages go to its own session. A cloud is
  // converted and filtered before the session's lock: the encoders keep flowing meanwhile.
  const auto hints = ros::TransportHints().tcpNoDelay();
  const EgoMotionSourceConfig& source = sessions_->sourceConfig(k);
  const auto feed = [this, k](const auto& event) {
    feedInput(*sessions_, adapter_->convert(*event.getConstMessage(), k, event.getPublisherName()));
  };
  ros::Subscriber subscriber;
  switch (source.type) {
    case EgoMotionSource::kScan:
      subscriber = subscribeEvents<sensor_msgs::LaserScan>(handle_, source.topic, 400, feed, hints);
      break;
    case EgoMotionSource::kCloud:
      subscriber =
          subscribeEvents<sensor_msgs::PointCloud2>(handle_, source.topic, 50, feed, hints);
      break;
    case EgoMotionSource::kOdometry:
      subscriber = subscribeEvents<nav_msgs::Odometry>(handle_, source.topic, 400, feed, hints);
      break;
    case EgoMotionSource::kPose:
      subscriber =
          subscribeEvents<geometry_msgs::PoseStamped>(handle_, source.topic, 400, feed, hints);
      break;
  }
  ego_subscribers_.push_back(subscriber);
}

}  // namespace odometry_calibration
