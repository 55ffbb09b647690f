#include "odometry_calibration/ros/point_cloud_conversion.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl_conversions/pcl_conversions.h>

namespace odometry_calibration {
namespace ros_conversions {
namespace {

using Field = sensor_msgs::PointField;

const Field* findField(const sensor_msgs::PointCloud2& message, const std::string& name)
{
  for (const Field& field : message.fields) {
    if (field.name == name)
      return &field;
  }
  return nullptr;
}

std::size_t fieldSize(std::uint8_t datatype)
{
  switch (datatype) {
    case Field::INT8:
    case Field::UINT8:
      return 1;
    case Field::INT16:
    case Field::UINT16:
      return 2;
    case Field::INT32:
    case Field::UINT32:
    case Field::FLOAT32:
      return 4;
    case Field::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

/// Reads one raw value of the given numeric type at `data`.
double readValue(const std::uint8_t* data, std::uint8_t datatype)
{
  auto as = [data](auto value) {
    std::memcpy(&value, data, sizeof value);
    return static_cast<double>(value);
  };
  switch (datatype) {
    case Field::INT8:
      return as(std::int8_t{});
    case Field::UINT8:
      return as(std::uint8_t{});
    case Field::INT16:
      return as(std::int16_t{});
    case Field::UINT16:
      return as(std::uint16_t{});
    case Field::INT32:
      return as(std::int32_t{});
    case Field::UINT32:
      return as(std::uint32_t{});
    case Field::FLOAT32:
      return as(float{});
    default:  // FLOAT64
      return as(double{});
  }
}

void checkLayout(const sensor_msgs::PointCloud2& message)
{
  const std::size_t points = static_cast<std::size_t>(message.width) * message.height;
  if (points > 0 &&
      (static_cast<std::size_t>(message.point_step) * message.width > message.row_step ||
       static_cast<std::size_t>(message.row_step) * message.height > message.data.size())) {
    throw std::invalid_argument("PointCloud2 data holds " + std::to_string(message.data.size()) +
                                " bytes, less than " + std::to_string(message.height) +
                                " rows of " + std::to_string(message.width) + " points of " +
                                std::to_string(message.point_step) + " bytes (row_step " +
                                std::to_string(message.row_step) + ")");
  }
  for (const Field& field : message.fields) {
    const std::size_t size = fieldSize(field.datatype);
    if (size == 0 ||
        static_cast<std::size_t>(field.offset) + size * std::max<std::uint32_t>(1, field.count) >
            message.point_step) {
      throw std::invalid_argument("PointCloud2 field '" + field.name +
                                  "' has an unknown type or lies beyond point_step " +
                                  std::to_string(message.point_step));
    }
  }
  for (const char* name : {"x", "y", "z"}) {
    const Field* field = findField(message, name);
    if (!field) {
      throw std::invalid_argument(std::string("PointCloud2 has no '") + name +
                                  "' field: not a cloud of 3D points");
    }
    if (field->datatype != Field::FLOAT32) {
      throw std::invalid_argument(std::string("PointCloud2 field '") + name +
                                  "' is not FLOAT32 (datatype " + std::to_string(field->datatype) +
                                  ")");
    }
  }
}

/// The field of the per-point times: the configured one, else the first of the usual names
/// the cloud has; nullptr when there is none.
const Field* timeField(const sensor_msgs::PointCloud2& message,
                       const PointTimeOptions& time_options)
{
  if (!time_options.field.empty())
    return findField(message, time_options.field);
  for (const std::string& name : defaultPointTimeFields()) {
    if (const Field* time = findField(message, name))
      return time;
  }
  return nullptr;
}

/// The message as PCL's, readable as PointXYZI: PCL fills PointXYZI's fields by name, so the
/// cloud's own intensity is set aside and x stands in for it (so that PCL finds every field);
/// the intensities are overwritten afterwards.
pcl::PCLPointCloud2 withStandInIntensity(const sensor_msgs::PointCloud2& message)
{
  pcl::PCLPointCloud2 pcl_message;
  pcl_conversions::toPCL(message, pcl_message);
  for (auto& field : pcl_message.fields) {
    if (field.name == "intensity")
      field.name = "intensity_of_the_cloud";
  }
  pcl::PCLPointField stand_in;
  stand_in.name = "intensity";
  stand_in.offset = findField(message, "x")->offset;
  stand_in.datatype = pcl::PCLPointField::FLOAT32;
  stand_in.count = 1;
  pcl_message.fields.push_back(stand_in);
  return pcl_message;
}

/// The points' times after the stamp [s] into the intensities of result.cloud, when the field's
/// values convert (else result.time_problem says why).
void readPointTimes(const sensor_msgs::PointCloud2& message, const Field& time,
                    const PointTimeOptions& time_options, LidarCloud& result)
{
  TimedCloud& cloud = *result.cloud;
  result.time_field = time.name;
  std::vector<double> times;
  times.reserve(cloud.size());
  for (std::uint32_t row = 0; row < message.height; ++row) {
    const std::uint8_t* row_data = message.data.data() + row * message.row_step;
    for (std::uint32_t column = 0; column < message.width; ++column)
      times.push_back(
          readValue(row_data + column * message.point_step + time.offset, time.datatype));
  }
  const bool integer_field = time.datatype != Field::FLOAT32 && time.datatype != Field::FLOAT64;
  const PointTimeConversion conversion =
      toTimesAfterStamp(times, integer_field, message.header.stamp.toSec(), time_options);
  result.time_unit = conversion.unit;
  result.time_reference = conversion.reference;
  if (conversion.usable() && times.size() == cloud.size()) {
    result.has_times = true;
    for (std::size_t i = 0; i < times.size(); ++i)
      cloud[i].intensity = static_cast<float>(times[i]);
  } else {
    result.time_problem = "per-point times of field '" + time.name +
                          "' ignored (no sweep compensation for this cloud): " + conversion.problem;
  }
}

}  // namespace

LidarCloud fromPointCloud2Msg(const sensor_msgs::PointCloud2& message,
                              const PointTimeOptions& time_options)
{
  checkLayout(message);
  const Field* time = timeField(message, time_options);
  const pcl::PCLPointCloud2 pcl_message = withStandInIntensity(message);
  LidarCloud result;
  result.cloud = std::make_shared<TimedCloud>();
  if (std::size_t{message.width} * message.height == 0)
    return result;  // no points (PCL's conversion would index the empty cloud's first point)
  pcl::fromPCLPointCloud2(pcl_message, *result.cloud);
  if (time) {
    readPointTimes(message, *time, time_options, result);
  } else if (!time_options.field.empty()) {
    result.time_problem = "the configured point_time_field '" + time_options.field +
                          "' is not in the cloud: no sweep compensation";
  }
  if (!result.has_times) {
    for (auto& point : result.cloud->points)
      point.intensity = 0.0f;
  }
  return result;
}

}  // namespace ros_conversions
}  // namespace odometry_calibration
