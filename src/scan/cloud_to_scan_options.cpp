#include "odometry_calibration/scan/cloud_to_scan_options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

void require(bool condition, const std::string& message)
{
  if (!condition)
    throw std::invalid_argument(message);
}

}  // namespace

const char* toString(ScanFrom from)
{
  return from == ScanFrom::kPoints ? "points" : "bins";
}

ScanFrom scanFromName(const std::string& name)
{
  if (name == "bins")
    return ScanFrom::kBins;
  if (name == "points")
    return ScanFrom::kPoints;
  throw std::invalid_argument("cloud scan_from must be bins or points, got '" + name + "'");
}

void validate(const CloudToScanOptions& o)
{
  require(std::isfinite(o.band_min_m) && std::isfinite(o.band_max_m) && o.band_min_m < o.band_max_m,
          "cloud band: need finite band_min_m < band_max_m");
  require(std::isfinite(o.roll_rad) && std::abs(o.roll_rad) < 0.5 * M_PI &&
              std::isfinite(o.pitch_rad) && std::abs(o.pitch_rad) < 0.5 * M_PI,
          "cloud roll_rad and pitch_rad must be finite and within (-pi/2, pi/2)");
  require(std::isfinite(o.voxel_size_m) && o.voxel_size_m >= 0.0,
          "cloud voxel_size_m must be >= 0 (0: no voxel grid)");
  require(o.outlier_neighbours >= 0, "cloud outlier_neighbours must be >= 0 (0: off)");
  require(std::isfinite(o.outlier_stddev) && o.outlier_stddev > 0.0,
          "cloud outlier_stddev must be > 0");
  require(std::isfinite(o.angular_resolution_rad) && o.angular_resolution_rad > 1e-5 &&
              o.angular_resolution_rad <= 0.1,
          "cloud angular_resolution_rad must be in (1e-5, 0.1] rad");
  require(std::isfinite(o.range_min_m) && o.range_min_m >= 0.0 && std::isfinite(o.range_max_m) &&
              o.range_max_m > o.range_min_m,
          "cloud ranges: need 0 <= range_min_m < range_max_m (finite)");
  require(o.min_points >= 1, "cloud min_points must be >= 1");
  validate(o.point_times);
}

std::string describeBand(const CloudToScanOptions& options)
{
  std::ostringstream text;
  text << "[" << options.band_min_m << ", " << options.band_max_m << "] m about the sensor's plane";
  if (options.roll_rad != 0.0 || options.pitch_rad != 0.0)
    text << " (levelled by roll " << options.roll_rad << ", pitch " << options.pitch_rad << " rad)";
  return text.str();
}

}  // namespace odometry_calibration
