#include "odometry_calibration/bag/rosbag_messages.h"

#include <ros/serialization.h>

#include "odometry_calibration/ros/wheel_tick_messages.h"

namespace odometry_calibration {

RosbagMessages::RosbagMessages(rosbag::View& view) : view_(view) {}

double RosbagMessages::beginTime_s() const
{
  return view_.getBeginTime().toSec();
}

double RosbagMessages::endTime_s() const
{
  return view_.getEndTime().toSec();
}

bool RosbagMessages::next()
{
  if (!started_) {
    current_ = view_.begin();
    end_ = view_.end();
    started_ = true;
  } else if (current_ != end_) {
    ++current_;
  }
  return current_ != end_;
}

const std::string& RosbagMessages::topic() const
{
  return current_->getTopic();
}

double RosbagMessages::recordTime_s() const
{
  return current_->getTime().toSec();
}

std::string RosbagMessages::publisher() const
{
  return current_->getCallerId();
}

template <typename T>
bool RosbagMessages::deserialiseChecked(T& message, ros_conversions::WireMessage type)
{
  const rosbag::MessageInstance& instance = *current_;
  const std::string md5 = instance.getMD5Sum();
  if (instance.getDataType() != ros::message_traits::datatype<T>() ||
      (md5 != "*" && md5 != ros::message_traits::md5sum<T>()))
    return false;
  bytes_.resize(instance.size());
  ros::serialization::OStream out(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
  instance.write(out);
  if (!ros_conversions::wireLengthsFit(type, bytes_.data(), bytes_.size())) {
    throw ros::Exception("a " + instance.getDataType() + " message on '" + instance.getTopic() +
                         "' at " + std::to_string(instance.getTime().toSec()) +
                         " s claims strings or arrays longer than its " +
                         std::to_string(bytes_.size()) + " bytes");
  }
  ros::serialization::IStream in(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
  ros::serialization::deserialize(in, message);
  return true;
}

bool RosbagMessages::read(sensor_msgs::JointState& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kJointState);
}

bool RosbagMessages::read(sensor_msgs::LaserScan& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kLaserScan);
}

bool RosbagMessages::read(sensor_msgs::PointCloud2& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kPointCloud2);
}

bool RosbagMessages::read(nav_msgs::Odometry& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kOdometry);
}

bool RosbagMessages::read(geometry_msgs::PoseStamped& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kPoseStamped);
}

bool RosbagMessages::read(sensor_msgs::Imu& message)
{
  return deserialiseChecked(message, ros_conversions::WireMessage::kImu);
}

bool RosbagMessages::readWheelTick(const std::string& type, double& value)
{
  return visitWheelTickType(type, [&](auto message) {
    using M = decltype(message);
    const rosbag::MessageInstance& instance = *current_;
    const std::string md5 = instance.getMD5Sum();
    if (instance.getDataType() != ros::message_traits::datatype<M>() ||
        (md5 != "*" && md5 != ros::message_traits::md5sum<M>()))
      return false;
    if (instance.size() != sizeof(message.data)) {  // a fixed size: no length to check
      throw ros::Exception("a " + instance.getDataType() + " message on '" + instance.getTopic() +
                           "' at " + std::to_string(instance.getTime().toSec()) + " s has " +
                           std::to_string(instance.size()) + " bytes, not " +
                           std::to_string(sizeof(message.data)));
    }
    bytes_.resize(instance.size());
    ros::serialization::OStream out(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
    instance.write(out);
    ros::serialization::IStream in(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
    ros::serialization::deserialize(in, message);
    value = static_cast<double>(message.data);
    return true;
  });
}

}  // namespace odometry_calibration
