// sensor_msgs/PointCloud2 of a 3D lidar into the core's TimedCloud (scan/cloud_to_scan.h), through
// pcl_conversions, with the per-point time that lidar drivers add.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include "odometry_calibration/scan/cloud_to_scan.h"

namespace odometry_calibration {
namespace ros_conversions {

/// A lidar cloud as the core takes it.
struct LidarCloud
{
  /// x, y, z in the message's frame; intensity = time after the stamp [s] (0 without times)
  TimedCloud::Ptr cloud;
  bool has_times = false;  ///< the message had a `time` or `t` field
};

/// Converts a PointCloud2: x, y, z (FLOAT32, as every lidar driver writes them) with PCL's
/// fromPCLPointCloud2, and the point times from a field named `time` or `t`: FLOAT32/FLOAT64 in
/// seconds, UINT32/INT32 in nanoseconds (e.g. Ouster's `t`), after the header stamp (a NaN time
/// anywhere: has_times false). Checks the
/// layout first (so that a malformed message never reads outside its data) and throws
/// std::invalid_argument naming the problem: a missing x/y/z field, a field of another type,
/// data shorter than width x height points, fields beyond point_step.
LidarCloud fromPointCloud2Msg(const sensor_msgs::PointCloud2& message);

}  // namespace ros_conversions
}  // namespace odometry_calibration
