// The options of the cloud-to-scan conversion (cloud_to_scan.h), apart so that configurations
// can hold them without PCL's headers.
#pragma once

#include <cstddef>
#include <string>

#include "odometry_calibration/scan/point_times.h"

namespace odometry_calibration {

/// What the matcher gets from the in-band points (config key ego_motion.cloud.scan_from).
enum class ScanFrom
{
  /// Binned by bearing: one ray per angular_resolution_rad, the nearest point of each bin.
  kBins,
  /// The points themselves: projected onto the plane before the voxel grid (rings that see the
  /// same wall merge into one voxel), then every voxel ordered by bearing, unbinned
  /// (Scan::ray_angles_rad).
  kPoints,
};

/// "bins" | "points".
const char* toString(ScanFrom from);

/// Parses "bins" or "points"; throws std::invalid_argument naming the choices otherwise.
ScanFrom scanFromName(const std::string& name);

/// How a cloud becomes a scan (config key ego_motion.cloud.*).
struct CloudToScanOptions
{
  ScanFrom scan_from = ScanFrom::kBins;  ///< binned scan or the points themselves
  double band_min_m = -0.3;              ///< height band, below the plane through the sensor [m]
  double band_max_m = 0.3;               ///< height band, above it [m]
  /// The sensor's tilt against the ground: rotating the cloud by R_y(pitch) R_x(roll) makes
  /// the plane ground-parallel [rad]. 0, 0 for a level sensor.
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double voxel_size_m = 0.05;               ///< VoxelGrid leaf size; 0 = off [m]
  int outlier_neighbours = 0;               ///< StatisticalOutlierRemoval's k; 0 = off
  double outlier_stddev = 1.0;              ///< its threshold (mean distance + this many sigma)
  double angular_resolution_rad = 0.00349;  ///< bearing bin = one ray of the scan (bins) [rad]
  double range_min_m = 0.3;                 ///< nearer points (the robot itself) dropped [m]
  double range_max_m = 60.0;                ///< farther points dropped [m]
  std::size_t min_points = 20;              ///< fewer rays left: the cloud is rejected
  PointTimeOptions point_times;             ///< which field holds the per-point times, and how
};

/// Throws std::invalid_argument naming the offending option.
void validate(const CloudToScanOptions& options);

/// The height band in words, for messages: "[-0.3, 0.3] m about the sensor's plane".
std::string describeBand(const CloudToScanOptions& options);

}  // namespace odometry_calibration
