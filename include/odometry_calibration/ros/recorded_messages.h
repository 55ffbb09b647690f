// Recorded messages as the bag reader takes them, whatever holds them: a ROS 1 bag
// (rosbag_messages.h) today, another bag format (rosbag2's SQLite or MCAP) behind the same
// interface later. A source walks its messages once, in record-time order, and deserialises the
// current one into the ROS 1 message types the input adapter converts (message_adapter.h).
#pragma once

#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

namespace odometry_calibration {

/// A cursor over recorded messages. Not thread-safe: one reader at a time.
class RecordedMessages
{
public:
  virtual ~RecordedMessages() = default;

  /// The record times of the first and last message [s] (for the progress of a run).
  virtual double beginTime_s() const = 0;
  virtual double endTime_s() const = 0;

  /// Moves to the next message (the first at the first call); false after the last one.
  virtual bool next() = 0;
  /// The current message's topic, record time [s] and publisher (the node that published it;
  /// empty when the recording does not say).
  virtual const std::string& topic() const = 0;
  virtual double recordTime_s() const = 0;
  virtual std::string publisher() const = 0;

  /// The current message deserialised into `message` when it is of that type (reusing its
  /// storage); false, `message` unspecified, when it is of another type. Throws
  /// ros::Exception (or std::runtime_error) for a message whose bytes do not hold what they claim.
  virtual bool read(sensor_msgs::JointState& message) = 0;
  virtual bool read(sensor_msgs::LaserScan& message) = 0;
  virtual bool read(sensor_msgs::PointCloud2& message) = 0;
  virtual bool read(nav_msgs::Odometry& message) = 0;
  virtual bool read(geometry_msgs::PoseStamped& message) = 0;
};

}  // namespace odometry_calibration
