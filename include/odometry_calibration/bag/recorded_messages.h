// Recorded messages as the bag reader takes them, whatever holds them: a ROS 1 bag
// (rosbag_messages.h), rosbag2's SQLite storage (rosbag2_sqlite_messages.h) or MCAP files
// (mcap_messages.h). A source walks its messages once, in record-time order, and deserialises the
// current one into the ROS 1 message types the input adapter converts (message_adapter.h).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

namespace odometry_calibration {

/// Thrown by RecordedMessages::read for one message whose bytes do not hold its type while the
/// recording around it is sound (a rosbag2 message cut short): the bag reader skips and counts
/// it as a bad input of its topic (converted_input.h). Its text names the topic, the record
/// time and the byte where the message fell short.
class UnreadableMessage : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

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
  /// UnreadableMessage for one message whose bytes do not hold what they claim (skipped), or
  /// ros::Exception (or std::runtime_error) when the recording itself is corrupted (the run
  /// stops).
  virtual bool read(sensor_msgs::JointState& message) = 0;
  virtual bool read(sensor_msgs::LaserScan& message) = 0;
  virtual bool read(sensor_msgs::PointCloud2& message) = 0;
  virtual bool read(nav_msgs::Odometry& message) = 0;
  virtual bool read(geometry_msgs::PoseStamped& message) = 0;
  virtual bool read(sensor_msgs::Imu& message) = 0;
  /// The current message's number when it is a wheel tick of std_msgs type `type`
  /// (wheel_tick_messages.h); false when it is of another type. Throws as read.
  virtual bool readWheelTick(const std::string& type, double& value) = 0;

  /// The files read only in part, each in words naming the file, the byte where reading
  /// stopped and why (a recording cut off while recording); empty when every file was read
  /// whole. Known once the source is open.
  virtual std::vector<std::string> partialReads() const { return {}; }
};

}  // namespace odometry_calibration
