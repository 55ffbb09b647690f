#include "odometry_calibration/bag/wire_length_check.h"

#include <cstdint>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/serialization.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

namespace odometry_calibration {
namespace {

using ros_conversions::wireLengthsFit;
using ros_conversions::WireMessage;

template <class Message>
std::vector<std::uint8_t> serialize(const Message& message)
{
  std::vector<std::uint8_t> bytes(ros::serialization::serializationLength(message));
  ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::serialize(out, message);
  return bytes;
}

void setU32(std::vector<std::uint8_t>* bytes, std::size_t at, std::uint32_t value)
{
  std::memcpy(bytes->data() + at, &value, 4);
}

sensor_msgs::JointState jointState()
{
  sensor_msgs::JointState message;
  message.header.frame_id = "base_link";
  message.name = {"left_wheel", "right_wheel"};
  message.position = {1.0, 2.0};
  return message;
}

// Byte offsets in jointState()'s serialisation: header 12 + 4 + 9 ("base_link") = 25, then the
// name count; the names take 2 x 4 + 10 + 11 bytes, then the position count at 25 + 4 + 29.
constexpr std::size_t kNameCount = 25;
constexpr std::size_t kPositionCount = 25 + 4 + 29;

TEST(WireLengthCheck, IntactMessagesFit)
{
  EXPECT_TRUE(wireLengthsFit(WireMessage::kJointState, serialize(jointState()).data(),
                             serialize(jointState()).size()));
  sensor_msgs::LaserScan scan;
  scan.ranges.assign(682, 1.0f);
  scan.intensities.assign(682, 3.0f);
  const auto scan_bytes = serialize(scan);
  EXPECT_TRUE(wireLengthsFit(WireMessage::kLaserScan, scan_bytes.data(), scan_bytes.size()));
  sensor_msgs::PointCloud2 cloud;
  cloud.fields.resize(3);
  cloud.fields[0].name = "x";
  cloud.fields[1].name = "y";
  cloud.fields[2].name = "intensity";
  cloud.data.assign(120, 7);
  const auto cloud_bytes = serialize(cloud);
  EXPECT_TRUE(wireLengthsFit(WireMessage::kPointCloud2, cloud_bytes.data(), cloud_bytes.size()));
  nav_msgs::Odometry odometry;
  odometry.child_frame_id = "base_link";
  const auto odometry_bytes = serialize(odometry);
  EXPECT_TRUE(wireLengthsFit(WireMessage::kOdometry, odometry_bytes.data(), odometry_bytes.size()));
}

TEST(WireLengthCheck, ACorruptedCountOrACutOffMessageDoesNotFit)
{
  auto bytes = serialize(jointState());
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + kNameCount, 4);
  ASSERT_EQ(count, 2u);  // the offsets above are right
  std::memcpy(&count, bytes.data() + kPositionCount, 4);
  ASSERT_EQ(count, 2u);

  auto names = bytes;
  setU32(&names, kNameCount, 0x7fffffffu);  // 2 G names: 64 GB of std::string in roscpp
  EXPECT_FALSE(wireLengthsFit(WireMessage::kJointState, names.data(), names.size()));
  auto positions = bytes;
  setU32(&positions, kPositionCount, 3);  // one double more than there is
  EXPECT_FALSE(wireLengthsFit(WireMessage::kJointState, positions.data(), positions.size()));
  auto frame = bytes;
  setU32(&frame, 12, 1000);  // frame_id longer than the message
  EXPECT_FALSE(wireLengthsFit(WireMessage::kJointState, frame.data(), frame.size()));
  EXPECT_FALSE(wireLengthsFit(WireMessage::kJointState, bytes.data(), bytes.size() - 1));
  EXPECT_FALSE(wireLengthsFit(WireMessage::kJointState, bytes.data(), 10));

  sensor_msgs::PointCloud2 cloud;
  cloud.data.assign(16, 1);
  auto cloud_bytes = serialize(cloud);
  // The data's count: before its 16 bytes and the final is_dense byte.
  setU32(&cloud_bytes, cloud_bytes.size() - 1 - 16 - 4, 0xffffffffu);
  EXPECT_FALSE(wireLengthsFit(WireMessage::kPointCloud2, cloud_bytes.data(), cloud_bytes.size()));
}

}  // namespace
}  // namespace odometry_calibration
