// A 3D lidar's point cloud turned into the planar scan the matcher takes.
//
// The cloud is in the sensor's frame. The points of a height band around the ground-parallel
// plane through the sensor are kept (the sensor's configured roll and pitch level the cloud
// first), thinned by a voxel grid and optionally cleaned of statistical outliers (PCL's CropBox,
// VoxelGrid and StatisticalOutlierRemoval), projected onto the plane and, with `scan_from: bins`,
// binned by bearing: each bin is one ray of the Scan, its range the nearest point's horizontal
// distance. Vertical walls seen by several rings land on the same bin, so the scan is the one a
// level 2D laser at the sensor's height would see. With `scan_from: points` the band is projected
// before the voxel grid (the rings that see a wall share its voxels, averaging their noise) and
// every voxel becomes a ray of its own at its own bearing (Scan::ray_angles_rad), ordered by
// bearing, as the matcher's line fits and angular search need. A point's time after the stamp
// (the lidar's per-point time field) becomes its ray's time (Scan::ray_times_s), for the sweep
// compensation of scan.h.
//
// Only x, y and the yaw of the sensor are observable from the resulting scans (planar motion):
// its height, roll and pitch are inputs (the band and the levelling), never estimated.
#pragma once

#include <cstddef>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "odometry_calibration/scan/cloud_to_scan_options.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// A lidar cloud in the sensor frame: x, y, z [m] and, in the `intensity` field, the point's
/// time after the cloud's stamp [s] (0 when the cloud carries no times). The intensity field is
/// borrowed so that PCL's precompiled filters carry the time along (a voxel's time is the mean
/// of its points').
using TimedCloud = pcl::PointCloud<pcl::PointXYZI>;

/// What became of a cloud's points, stage by stage.
struct CloudToScanCounts
{
  std::size_t input = 0;   ///< points in the cloud
  std::size_t finite = 0;  ///< with finite x, y, z
  std::size_t band = 0;    ///< in the height band and range box
  std::size_t voxels = 0;  ///< after the voxel grid
  std::size_t kept = 0;    ///< after the outlier removal
  std::size_t rays = 0;    ///< scan rays holding a point (points: the kept points in range)
};

/// The scan of `cloud` (see the file comment): bins: rays of width angular_resolution_rad
/// covering [-pi, pi), NaN where no point fell; points: one ray per kept point, by bearing.
/// ray_times_s from the points' times when `has_times`.
/// Throws std::invalid_argument for an empty cloud, and for one with fewer than min_points rays
/// left, naming the band and how many points remained after each stage. `counts`, if given,
/// receives the counts (also when it throws).
Scan cloudToScan(const TimedCloud::ConstPtr& cloud, bool has_times,
                 const CloudToScanOptions& options, CloudToScanCounts* counts = nullptr);

}  // namespace odometry_calibration
