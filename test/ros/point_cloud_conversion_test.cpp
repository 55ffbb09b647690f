// PointCloud2 -> the core's cloud: x, y, z through pcl_conversions, the drivers' time fields,
// and the messages that are refused (each naming its problem).
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/ros/point_cloud_conversion.h"

namespace odometry_calibration {
namespace {

using ros_conversions::fromPointCloud2Msg;
using Field = sensor_msgs::PointField;

/// A cloud of n points with the given fields (name, datatype), packed in that order; point i
/// has x = i, y = 2 i, z = -i and time field value i (seconds) or 1000000 i (nanoseconds).
sensor_msgs::PointCloud2 makeCloud(const std::vector<std::pair<std::string, std::uint8_t>>& fields,
                                   std::size_t n)
{
  sensor_msgs::PointCloud2 message;
  message.header.frame_id = "lidar";
  std::uint32_t offset = 0;
  for (const auto& [name, datatype] : fields) {
    Field field;
    field.name = name;
    field.offset = offset;
    field.datatype = datatype;
    field.count = 1;
    message.fields.push_back(field);
    offset += datatype == Field::FLOAT64 ? 8 : (datatype == Field::UINT16 ? 2 : 4);
  }
  message.point_step = offset;
  message.width = static_cast<std::uint32_t>(n);
  message.height = 1;
  message.row_step = message.point_step * message.width;
  message.data.resize(message.row_step);
  for (std::size_t i = 0; i < n; ++i) {
    for (const Field& field : message.fields) {
      std::uint8_t* out = message.data.data() + i * message.point_step + field.offset;
      const double value = field.name == "x"   ? static_cast<double>(i)
                           : field.name == "y" ? 2.0 * static_cast<double>(i)
                           : field.name == "z" ? -static_cast<double>(i)
                                               : 0.001 * static_cast<double>(i);
      if (field.datatype == Field::FLOAT32) {
        const float v = static_cast<float>(value);
        std::memcpy(out, &v, 4);
      } else if (field.datatype == Field::FLOAT64) {
        std::memcpy(out, &value, 8);
      } else if (field.datatype == Field::UINT32) {
        const std::uint32_t v = static_cast<std::uint32_t>(std::lround(value * 1e9));
        std::memcpy(out, &v, 4);
      } else if (field.datatype == Field::UINT16) {
        const std::uint16_t v = static_cast<std::uint16_t>(i % 16);
        std::memcpy(out, &v, 2);
      }
    }
  }
  return message;
}

/// The message of what fromPointCloud2Msg throws ("" if it does not).
std::string refusal(const sensor_msgs::PointCloud2& message)
{
  try {
    fromPointCloud2Msg(message);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(PointCloudConversion, VelodyneLayoutGivesPointsAndTimes)
{
  const auto message = makeCloud({{"x", Field::FLOAT32},
                                  {"y", Field::FLOAT32},
                                  {"z", Field::FLOAT32},
                                  {"intensity", Field::FLOAT32},
                                  {"ring", Field::UINT16},
                                  {"time", Field::FLOAT32}},
                                 50);
  const auto cloud = fromPointCloud2Msg(message);
  ASSERT_EQ(cloud.cloud->size(), 50u);
  EXPECT_TRUE(cloud.has_times);
  EXPECT_FLOAT_EQ((*cloud.cloud)[7].x, 7.0f);
  EXPECT_FLOAT_EQ((*cloud.cloud)[7].y, 14.0f);
  EXPECT_FLOAT_EQ((*cloud.cloud)[7].z, -7.0f);
  EXPECT_FLOAT_EQ((*cloud.cloud)[7].intensity, 0.007f);  // the time, not the intensity
}

TEST(PointCloudConversion, OusterNanosecondTimesBecomeSeconds)
{
  const auto message = makeCloud(
      {{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}, {"t", Field::UINT32}},
      20);
  const auto cloud = fromPointCloud2Msg(message);
  EXPECT_TRUE(cloud.has_times);
  EXPECT_NEAR((*cloud.cloud)[19].intensity, 0.019, 1e-7);
}

TEST(PointCloudConversion, WithoutATimeFieldThereAreNoTimes)
{
  const auto cloud = fromPointCloud2Msg(
      makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 5));
  EXPECT_FALSE(cloud.has_times);
  EXPECT_FLOAT_EQ((*cloud.cloud)[4].intensity, 0.0f);
}

TEST(PointCloudConversion, ANanTimeDropsTheTimes)
{
  auto message = makeCloud({{"x", Field::FLOAT32},
                            {"y", Field::FLOAT32},
                            {"z", Field::FLOAT32},
                            {"time", Field::FLOAT32}},
                           5);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(message.data.data() + 2 * message.point_step + 12, &nan, 4);
  const auto cloud = fromPointCloud2Msg(message);
  EXPECT_FALSE(cloud.has_times);
  EXPECT_NE(cloud.time_problem.find("point 2's time is nan"), std::string::npos)
      << cloud.time_problem;
}

TEST(PointCloudConversion, NanPointsPassThroughForTheFilterToDrop)
{
  auto message =
      makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(message.data.data() + message.point_step, &nan, 4);
  const auto cloud = fromPointCloud2Msg(message);
  ASSERT_EQ(cloud.cloud->size(), 3u);
  EXPECT_TRUE(std::isnan((*cloud.cloud)[1].x));
}

/// Overwrites the FLOAT64 field `name` of every point i with value(i).
template <typename Value>
void setFloat64(sensor_msgs::PointCloud2& message, const std::string& name, Value value)
{
  for (const Field& field : message.fields) {
    if (field.name != name)
      continue;
    for (std::size_t i = 0; i < message.width; ++i) {
      const double v = value(i);
      std::memcpy(message.data.data() + i * message.point_step + field.offset, &v, 8);
    }
  }
}

constexpr double kStamp = 1700000000.5;  // header stamp [s since the epoch]

/// Hesai's layout: x, y, z, intensity, ring, `timestamp` (FLOAT64), stamped kStamp.
sensor_msgs::PointCloud2 hesaiCloud(std::size_t n)
{
  auto message = makeCloud({{"x", Field::FLOAT32},
                            {"y", Field::FLOAT32},
                            {"z", Field::FLOAT32},
                            {"intensity", Field::FLOAT32},
                            {"ring", Field::UINT16},
                            {"timestamp", Field::FLOAT64}},
                           n);
  message.header.stamp.fromSec(kStamp);
  return message;
}

TEST(PointCloudConversion, HesaiAbsoluteSecondsBecomeTimesAfterTheStamp)
{
  auto message = hesaiCloud(20);
  setFloat64(message, "timestamp",
             [](std::size_t i) { return kStamp + 0.001 * static_cast<double>(i); });
  const auto cloud = fromPointCloud2Msg(message);
  EXPECT_TRUE(cloud.has_times) << cloud.time_problem;
  EXPECT_TRUE(cloud.time_problem.empty());
  EXPECT_EQ(cloud.time_field, "timestamp");
  EXPECT_EQ(cloud.time_unit, PointTimeUnit::kSeconds);
  EXPECT_EQ(cloud.time_reference, PointTimeReference::kAbsolute);
  EXPECT_NEAR((*cloud.cloud)[0].intensity, 0.0, 1e-6);
  EXPECT_NEAR((*cloud.cloud)[19].intensity, 0.019, 1e-6);
  EXPECT_FLOAT_EQ((*cloud.cloud)[19].x, 19.0f);
}

TEST(PointCloudConversion, LivoxAbsoluteNanosecondsBecomeTimesAfterTheStamp)
{
  auto message = hesaiCloud(20);
  setFloat64(message, "timestamp",
             [](std::size_t i) { return (kStamp + 0.001 * static_cast<double>(i)) * 1e9; });
  const auto cloud = fromPointCloud2Msg(message);
  EXPECT_TRUE(cloud.has_times) << cloud.time_problem;
  EXPECT_EQ(cloud.time_unit, PointTimeUnit::kNanoseconds);
  EXPECT_EQ(cloud.time_reference, PointTimeReference::kAbsolute);
  EXPECT_NEAR((*cloud.cloud)[19].intensity, 0.019, 1e-6);
}

TEST(PointCloudConversion, ABadAbsoluteTimeLeavesTheCloudWithoutTimesSayingWhy)
{
  // One point carries another sweep's time, 3 s later: no compensation rather than a wrong one.
  auto message = hesaiCloud(20);
  setFloat64(message, "timestamp", [](std::size_t i) {
    return kStamp + 0.001 * static_cast<double>(i) + (i == 11 ? 3.0 : 0.0);
  });
  const auto cloud = fromPointCloud2Msg(message);
  EXPECT_FALSE(cloud.has_times);
  EXPECT_NE(cloud.time_problem.find("per-point times of field 'timestamp' ignored"),
            std::string::npos)
      << cloud.time_problem;
  EXPECT_NE(cloud.time_problem.find("point 11's time is 3.011 s from the stamp"), std::string::npos)
      << cloud.time_problem;
  for (const auto& point : cloud.cloud->points)
    EXPECT_EQ(point.intensity, 0.0f);
  ASSERT_EQ(cloud.cloud->size(), 20u);  // the points themselves are kept

  // A NaN absolute time likewise.
  setFloat64(message, "timestamp", [](std::size_t i) {
    return i == 4 ? std::numeric_limits<double>::quiet_NaN()
                  : kStamp + 0.001 * static_cast<double>(i);
  });
  const auto nan = fromPointCloud2Msg(message);
  EXPECT_FALSE(nan.has_times);
  EXPECT_NE(nan.time_problem.find("point 4's time is nan"), std::string::npos) << nan.time_problem;
}

TEST(PointCloudConversion, TheConfiguredTimeFieldIsUsedOrItsAbsenceNamed)
{
  const auto message = makeCloud({{"x", Field::FLOAT32},
                                  {"y", Field::FLOAT32},
                                  {"z", Field::FLOAT32},
                                  {"offset_time", Field::UINT32}},
                                 20);
  // Not one of the names tried by default: no times, and nothing wrong.
  const auto by_default = fromPointCloud2Msg(message);
  EXPECT_FALSE(by_default.has_times);
  EXPECT_TRUE(by_default.time_problem.empty());
  PointTimeOptions options;
  options.field = "offset_time";
  const auto configured = fromPointCloud2Msg(message, options);
  EXPECT_TRUE(configured.has_times) << configured.time_problem;
  EXPECT_NEAR((*configured.cloud)[19].intensity, 0.019, 1e-7);
  options.field = "point_time";
  const auto missing = fromPointCloud2Msg(message, options);
  EXPECT_FALSE(missing.has_times);
  EXPECT_NE(missing.time_problem.find("point_time_field 'point_time' is not in the cloud"),
            std::string::npos)
      << missing.time_problem;
}

TEST(PointCloudConversion, MalformedCloudsAreRefusedSayingWhy)
{
  EXPECT_EQ(refusal(makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}}, 4)),
            "PointCloud2 has no 'z' field: not a cloud of 3D points");
  EXPECT_NE(
      refusal(makeCloud({{"x", Field::FLOAT64}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 4))
          .find("field 'x' is not FLOAT32"),
      std::string::npos);
  auto short_data =
      makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 4);
  short_data.data.resize(20);
  EXPECT_NE(refusal(short_data).find("data holds 20 bytes, less than 1 rows of 4 points"),
            std::string::npos)
      << refusal(short_data);
  auto beyond = makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 4);
  beyond.fields[2].offset = 10;  // z would end at byte 14 of a 12-byte point
  EXPECT_NE(refusal(beyond).find("field 'z'"), std::string::npos);
  // No points at all: a valid, empty cloud (cloudToScan says "the cloud is empty").
  EXPECT_TRUE(
      fromPointCloud2Msg(
          makeCloud({{"x", Field::FLOAT32}, {"y", Field::FLOAT32}, {"z", Field::FLOAT32}}, 0))
          .cloud->empty());
}

}  // namespace
}  // namespace odometry_calibration
