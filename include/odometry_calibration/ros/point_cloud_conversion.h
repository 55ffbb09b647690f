// sensor_msgs/PointCloud2 of a 3D lidar into the core's TimedCloud (scan/cloud_to_scan.h), through
// pcl_conversions, with the per-point time that lidar drivers add.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include "odometry_calibration/scan/cloud_to_scan.h"
#include "odometry_calibration/scan/point_times.h"

namespace odometry_calibration {
namespace ros_conversions {

/// A lidar cloud as the core takes it.
struct LidarCloud
{
  /// x, y, z in the message's frame; intensity = time after the stamp [s] (0 without times)
  TimedCloud::Ptr cloud;
  bool has_times = false;  ///< the message had a time field with usable times
  std::string time_field;  ///< the time field found (empty: none)
  PointTimeUnit time_unit = PointTimeUnit::kAuto;  ///< how its values were read
  PointTimeReference time_reference = PointTimeReference::kAuto;
  /// Not empty when the cloud's times were not used (a bad time, or the configured field is
  /// missing): why, in words. The cloud itself is usable (without sweep compensation); the
  /// caller counts and reports these.
  std::string time_problem;
};

/// Converts a PointCloud2: x, y, z (FLOAT32, as every lidar driver writes them) with PCL's
/// fromPCLPointCloud2, and the per-point times from `time_options.field` or else the first of
/// `time`, `t`, `timestamp` present (any numeric type), made seconds after the header stamp by
/// toTimesAfterStamp (point_times.h: Velodyne's relative FLOAT32 s, Ouster's relative UINT32
/// ns, Hesai's absolute FLOAT64 s, Livox's absolute FLOAT64 ns). A cloud with any time that is
/// not finite or lies beyond time_options.limit_s of the stamp keeps no times (has_times false,
/// time_problem says why). Checks the layout first (so that a malformed message never reads
/// outside its data) and throws std::invalid_argument naming the problem: a missing x/y/z
/// field, a field of another type, data shorter than width x height points, fields beyond
/// point_step.
LidarCloud fromPointCloud2Msg(const sensor_msgs::PointCloud2& message,
                              const PointTimeOptions& time_options = {});

}  // namespace ros_conversions
}  // namespace odometry_calibration
