// The recorded messages of a ROS 1 bag view (rosbag's C++ API), for the bag reader
// (recorded_messages.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <rosbag/view.h>

#include "odometry_calibration/bag/recorded_messages.h"
#include "odometry_calibration/bag/wire_length_check.h"

namespace odometry_calibration {

/// A rosbag::View's messages, in its order. Each message's bytes are copied out of its chunk
/// (checkBagRecords vouched that they lie inside it) and their string and array lengths checked
/// (wire_length_check.h) before deserialising: a corrupted array count would otherwise make
/// roscpp allocate up to 4 G elements before it notices the bytes are missing.
class RosbagMessages : public RecordedMessages
{
public:
  /// Walks `view`, which must outlive this.
  explicit RosbagMessages(rosbag::View& view);

  double beginTime_s() const override;
  double endTime_s() const override;
  bool next() override;
  const std::string& topic() const override;
  double recordTime_s() const override;
  std::string publisher() const override;
  /// Throws ros::Exception for lengths beyond the message's bytes.
  bool read(sensor_msgs::JointState& message) override;
  bool read(sensor_msgs::LaserScan& message) override;
  bool read(sensor_msgs::PointCloud2& message) override;
  bool read(nav_msgs::Odometry& message) override;
  bool read(geometry_msgs::PoseStamped& message) override;
  bool read(sensor_msgs::Imu& message) override;
  bool readWheelTick(const std::string& type, double& value) override;

private:
  /// The current message as T (serialised as `type`) into `message` (see
  /// RecordedMessages::read).
  template <typename T>
  bool deserialiseChecked(T& message, ros_conversions::WireMessage type);

  rosbag::View& view_;
  rosbag::View::iterator current_, end_;
  bool started_ = false;
  std::vector<std::uint8_t> bytes_;  ///< the message being deserialised
};

}  // namespace odometry_calibration
