#include "odometry_calibration/bag/wire_length_check.h"

#include <cstring>

namespace odometry_calibration {
namespace ros_conversions {
namespace {

/// A cursor over the bytes that turns false, and stays so, at the first length beyond them.
class WireWalker
{
public:
  WireWalker(const std::uint8_t* data, std::size_t size) : data_(data), left_(size) {}

  bool ok() const { return ok_; }

  void skip(std::size_t bytes)
  {
    if (!ok_ || bytes > left_) {
      ok_ = false;
      left_ = 0;
      return;
    }
    data_ += bytes;
    left_ -= bytes;
  }

  std::uint32_t u32()
  {
    std::uint32_t value = 0;
    if (ok_ && left_ >= 4)
      std::memcpy(&value, data_, 4);  // the wire is little-endian, as every ROS 1 host
    skip(4);
    return value;
  }

  void string() { skip(u32()); }

  /// std_msgs/Header: uint32 seq, time stamp (2 x uint32), string frame_id.
  void header()
  {
    skip(12);
    string();
  }

  /// An array of `count` fixed-size elements of `element_bytes` each.
  void fixedArray(std::size_t element_bytes) { skip(std::size_t{u32()} * element_bytes); }

  /// An array of elements that each start with a string and then have `tail_bytes` fixed bytes
  /// (strings: 0; sensor_msgs/PointField: uint32 offset, uint8 datatype, uint32 count = 9).
  void stringLedArray(std::size_t tail_bytes)
  {
    const std::uint32_t count = u32();
    // Each element takes at least 4 + tail_bytes: refuse a count beyond that before walking.
    if (count > left_ / (4 + tail_bytes)) {
      skip(left_ + 1);
      return;
    }
    for (std::uint32_t i = 0; i < count && ok_; ++i) {
      string();
      skip(tail_bytes);
    }
  }

private:
  const std::uint8_t* data_;
  std::size_t left_;
  bool ok_ = true;
};

}  // namespace

std::string wireMessageName(WireMessage type)
{
  switch (type) {
    case WireMessage::kJointState:
      return "sensor_msgs/JointState";
    case WireMessage::kLaserScan:
      return "sensor_msgs/LaserScan";
    case WireMessage::kPointCloud2:
      return "sensor_msgs/PointCloud2";
    case WireMessage::kOdometry:
      return "nav_msgs/Odometry";
    case WireMessage::kPoseStamped:
      return "geometry_msgs/PoseStamped";
    case WireMessage::kImu:
      return "sensor_msgs/Imu";
  }
  return "unknown message";
}

bool wireLengthsFit(WireMessage type, const std::uint8_t* data, std::size_t size)
{
  WireWalker walk(data, size);
  walk.header();
  switch (type) {
    case WireMessage::kJointState:
      walk.stringLedArray(0);  // name
      walk.fixedArray(8);      // position
      walk.fixedArray(8);      // velocity
      walk.fixedArray(8);      // effort
      break;
    case WireMessage::kLaserScan:
      walk.skip(7 * 4);    // angle_min, angle_max, angle_increment, time_increment,
                           // scan_time, range_min, range_max (float32)
      walk.fixedArray(4);  // ranges
      walk.fixedArray(4);  // intensities
      break;
    case WireMessage::kPointCloud2:
      walk.skip(2 * 4);        // height, width
      walk.stringLedArray(9);  // fields
      walk.skip(1 + 2 * 4);    // is_bigendian, point_step, row_step
      walk.fixedArray(1);      // data
      walk.skip(1);            // is_dense
      break;
    case WireMessage::kOdometry:
      walk.string();                     // child_frame_id
      walk.skip((7 + 36 + 6 + 36) * 8);  // pose, its covariance, twist, its covariance
      break;
    case WireMessage::kPoseStamped:
      walk.skip(7 * 8);  // position, orientation
      break;
    case WireMessage::kImu:
      walk.skip((4 + 9 + 3 + 9 + 3 + 9) * 8);  // orientation, angular velocity, acceleration
      break;
  }
  return walk.ok();
}

}  // namespace ros_conversions
}  // namespace odometry_calibration
