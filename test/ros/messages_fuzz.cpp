// Fuzz target: the live node's inputs as bytes on the wire. Each input is a sequence of
// messages, each a type byte then the message serialised by ros::serialization (JointState,
// LaserScan, Odometry, PoseStamped); they are deserialised and go through the node's own
// conversions, the glitch filter and pairing (PairCollector), and the odometry integration,
// with the diff_drive.yaml configuration. The first byte picks the ego-motion source (scans or
// poses), as the node's configuration does.
#include <cstdint>
#include <memory>
#include <stdexcept>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/serialization.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

#include "odometry_calibration/bag/wire_length_check.h"
#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/ros/conversions.h"

#include "support/fuzz_config.h"

using namespace odometry_calibration;
namespace ser = ros::serialization;

namespace {

/// The wire types of the input's type byte (mod 4).
const ros_conversions::WireMessage kWireTypes[] = {
    ros_conversions::WireMessage::kJointState, ros_conversions::WireMessage::kLaserScan,
    ros_conversions::WireMessage::kOdometry, ros_conversions::WireMessage::kPoseStamped};

template <class Message>
Message read(ser::IStream& stream)
{
  Message message;
  ser::deserialize(stream, message);
  return message;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const CalibrationConfig& config = test::diffDriveFuzzConfig();
  if (size < 1)
    return 0;
  const bool scans = data[0] % 2 == 0;
  const std::vector<EncoderChannelOptions> channels = encoderChannels(config);
  PairCollector collector(channels, config.collector, priorPredictor(config));
  EncoderDecoder decoder(channels);
  OdometryIntegrator odometry(priorModel(config), priorSensorPose(config),
                              config.collector.keyframe_interval_s);
  const Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-4;
  ser::IStream stream(const_cast<std::uint8_t*>(data) + 1, static_cast<uint32_t>(size - 1));
  try {
    while (stream.getLength() > 0) {
      std::uint8_t type = 0;
      ser::deserialize(stream, type);
      // roscpp would allocate what the lengths claim before finding the bytes missing: its
      // limitation (every node's), not this package's, so such input is not passed on.
      if (!ros_conversions::wireLengthsFit(kWireTypes[type % 4], stream.getData(),
                                           stream.getLength()))
        break;
      try {
        switch (type % 4) {
          case 0: {
            const auto message = read<sensor_msgs::JointState>(stream);
            const Eigen::VectorXd raw =
                applySigns(config, ros_conversions::rawJointPositions(message, channels));
            const double stamp_s = message.header.stamp.toSec();
            Eigen::VectorXd accepted;
            collector.addEncoders(stamp_s, raw, &accepted);
            try {
              if (accepted.size() > 0)
                odometry.add({stamp_s, decoder.decode(accepted)});
            } catch (const std::exception&) {
              // The node warns and goes on.
            }
            break;
          }
          case 1: {
            const auto message = read<sensor_msgs::LaserScan>(stream);
            const Scan scan = ros_conversions::fromLaserScanMsg(message);
            if (scans &&
                static_cast<int>(countUsableReadings(scan)) >= config.collector.plicp.min_points)
              collector.addScan(message.header.stamp.toSec(), scan);
            break;
          }
          case 2: {
            const auto message = read<nav_msgs::Odometry>(stream);
            const Pose2 pose = ros_conversions::fromPoseMsg(message.pose.pose);
            if (!scans)
              collector.addSensorPose(message.header.stamp.toSec(), pose, covariance);
            break;
          }
          default: {
            const auto message = read<geometry_msgs::PoseStamped>(stream);
            const Pose2 pose = ros_conversions::fromPoseMsg(message.pose);
            if (!scans)
              collector.addSensorPose(message.header.stamp.toSec(), pose, covariance);
            break;
          }
        }
      } catch (const std::invalid_argument&) {
        // A message the node skips (and counts).
      }
    }
    collector.flush();
  } catch (const ser::StreamOverrunException&) {
    // Bytes that end inside a message: roscpp drops such a message.
  } catch (const std::runtime_error&) {
    // ros::Time out of range: roscpp throws while deserialising, the message is dropped.
  }
  return 0;
}
