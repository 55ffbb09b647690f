#include "odometry_calibration/ros/message_adapter.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/scan/pcl_support.h"
#include "odometry_calibration/session/calibration_session.h"
#if ODOMETRY_CALIBRATION_HAVE_PCL
#include "odometry_calibration/ros/point_cloud_conversion.h"
#include "odometry_calibration/scan/cloud_to_scan.h"
#endif

namespace odometry_calibration {
namespace {

/// An input of `kind` from source `source` with the message's stamp and publisher.
ConvertedInput makeInput(ConvertedInput::Kind kind, std::size_t source, const ros::Time& stamp,
                         std::string publisher)
{
  ConvertedInput input;
  input.kind = kind;
  input.source = source;
  input.stamp_s = stamp.toSec();
  input.publisher = std::move(publisher);
  return input;
}

/// `input` made a bad ego-motion message of `message_type`, for `problem`.
void markBadEgoMessage(ConvertedInput& input, const char* message_type, const std::string& problem)
{
  input.kind = ConvertedInput::Kind::kBadEgoMessage;
  input.message_type = message_type;
  input.problem = problem;
}

/// A pose message's pose as source `source`'s sensor pose in `frame`, or a bad "pose".
ConvertedInput sensorPose(const geometry_msgs::Pose& pose, const ros::Time& stamp,
                          const std::string& frame, std::size_t source, std::string publisher)
{
  ConvertedInput input =
      makeInput(ConvertedInput::Kind::kSensorPose, source, stamp, std::move(publisher));
  try {
    input.pose = ros_conversions::fromPoseMsg(pose);
    input.frame = frame;
  } catch (const std::invalid_argument& error) {
    markBadEgoMessage(input, "pose", error.what());
  }
  return input;
}

}  // namespace

MessageAdapter::MessageAdapter(const CalibrationConfig& config)
    : config_(config), channels_(encoderChannels(config))
{
}

ConvertedInput MessageAdapter::convert(const sensor_msgs::JointState& message,
                                       std::string publisher) const
{
  ConvertedInput input =
      makeInput(ConvertedInput::Kind::kJoints, 0, message.header.stamp, std::move(publisher));
  try {
    if (config_.wheels.source == WheelSource::kJointVelocity) {
      input.kind = ConvertedInput::Kind::kJointVelocities;
      input.raw = ros_conversions::rawJointVelocities(message, channels_);
    } else {
      input.raw = applySigns(config_, ros_conversions::rawJointPositions(message, channels_));
    }
  } catch (const std::invalid_argument& error) {
    input.kind = ConvertedInput::Kind::kBadJoints;
    input.problem = error.what();
  }
  return input;
}

ConvertedInput MessageAdapter::convertWheelTick(double value, std::size_t wheel, double time_s,
                                                std::string publisher) const
{
  ConvertedInput input;
  input.kind = ConvertedInput::Kind::kWheelTick;
  input.wheel = wheel;
  input.stamp_s = time_s;
  input.publisher = std::move(publisher);
  input.raw = Eigen::VectorXd::Constant(1, value);
  if (!std::isfinite(value)) {
    input.kind = ConvertedInput::Kind::kBadJoints;
    const std::string topic = wheel < config_.wheels.topics.size()
                                  ? " on '" + config_.wheels.topics[wheel] + "'"
                                  : std::string();
    input.problem = "a wheel tick" + topic + " that is not a finite number";
  }
  return input;
}

ConvertedInput MessageAdapter::convertBaseOdometry(const nav_msgs::Odometry& message,
                                                   std::string publisher) const
{
  ConvertedInput input =
      makeInput(ConvertedInput::Kind::kBaseOdometry, 0, message.header.stamp, std::move(publisher));
  try {
    input.pose = ros_conversions::fromPoseMsg(message.pose.pose);
  } catch (const std::invalid_argument& error) {
    input.kind = ConvertedInput::Kind::kBadJoints;
    input.problem = std::string("a base odometry message: ") + error.what();
  }
  return input;
}

ConvertedInput MessageAdapter::convert(const sensor_msgs::LaserScan& message, std::size_t source,
                                       std::string publisher) const
{
  ConvertedInput input =
      makeInput(ConvertedInput::Kind::kScan, source, message.header.stamp, std::move(publisher));
  input.frame = message.header.frame_id;
  if (const std::string problem = scanRaysProblem(message.ranges.size(), config_.max_scan_rays);
      !problem.empty()) {  // refused before it is copied
    markBadEgoMessage(input, "LaserScan", problem);
    return input;
  }
  try {
    input.scan = ros_conversions::fromLaserScanMsg(message);
  } catch (const std::invalid_argument& error) {
    markBadEgoMessage(input, "LaserScan", error.what());
  }
  return input;
}

ConvertedInput MessageAdapter::convert(const sensor_msgs::PointCloud2& message, std::size_t source,
                                       std::string publisher, double* filtering_s) const
{
  ConvertedInput input = makeInput(ConvertedInput::Kind::kCloudScan, source, message.header.stamp,
                                   std::move(publisher));
  input.frame = message.header.frame_id;
#if !ODOMETRY_CALIBRATION_HAVE_PCL  // the session refuses a cloud source before any message
  markBadEgoMessage(input, "PointCloud2", withoutPclMessage("turning a cloud into a scan"));
  (void)filtering_s;
#else
  using Clock = std::chrono::steady_clock;
  try {
    const auto lidar = ros_conversions::fromPointCloud2Msg(message, config_.cloud.point_times);
    const auto filtering_start = Clock::now();
    try {
      input.scan = cloudToScan(lidar.cloud, lidar.has_times, config_.cloud);
      input.problem = lidar.time_problem;
    } catch (const std::invalid_argument& error) {
      markBadEgoMessage(input, "PointCloud2", error.what());
    }
    if (filtering_s)
      *filtering_s += std::chrono::duration<double>(Clock::now() - filtering_start).count();
  } catch (const std::invalid_argument& error) {
    markBadEgoMessage(input, "PointCloud2", error.what());
  }
#endif
  return input;
}

ConvertedInput MessageAdapter::convert(const nav_msgs::Odometry& message, std::size_t source,
                                       std::string publisher) const
{
  return sensorPose(message.pose.pose, message.header.stamp, message.child_frame_id, source,
                    std::move(publisher));
}

ConvertedInput MessageAdapter::convert(const geometry_msgs::PoseStamped& message,
                                       std::size_t source, std::string publisher) const
{
  return sensorPose(message.pose, message.header.stamp, "", source, std::move(publisher));
}

ConvertedInput MessageAdapter::convert(const sensor_msgs::Imu& message, std::string publisher) const
{
  ConvertedInput input;
  input.kind = ConvertedInput::Kind::kGyro;
  input.stamp_s = message.header.stamp.toSec();
  input.raw = Eigen::Vector3d(message.angular_velocity.x, message.angular_velocity.y,
                              message.angular_velocity.z);
  input.frame = message.header.frame_id;
  input.publisher = std::move(publisher);
  return input;
}

}  // namespace odometry_calibration
