#include "odometry_calibration/scan/scan.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {

void validate(const Scan& scan)
{
  if (!std::isfinite(scan.angle_increment_rad) || scan.angle_increment_rad == 0.0) {
    throw std::invalid_argument("scan angle_increment_rad must be a non-zero number of radians");
  }
  if (!std::isfinite(scan.angle_min_rad)) {
    throw std::invalid_argument("scan angle_min_rad must be a finite number of radians");
  }
  if (!std::isfinite(scan.range_min_m) || scan.range_min_m < 0.0) {
    throw std::invalid_argument("scan range_min_m must be a finite number of metres >= 0");
  }
  // range_max may be +inf (no upper limit) but must exceed range_min.
  if (std::isnan(scan.range_max_m) || !(scan.range_max_m > scan.range_min_m)) {
    throw std::invalid_argument("scan range_max_m must be larger than range_min_m");
  }
  if (!scan.valid.empty() && scan.valid.size() != scan.ranges_m.size()) {
    throw std::invalid_argument("scan valid mask has " + std::to_string(scan.valid.size()) +
                                " entries for " + std::to_string(scan.ranges_m.size()) +
                                " rays: give one per ray, or leave it empty");
  }
}

ScanPoints scanToPoints(const Scan& scan)
{
  validate(scan);
  ScanPoints result;
  const std::size_t ray_count = scan.ranges_m.size();
  result.points_m.reserve(ray_count);
  result.directions.reserve(ray_count);
  result.angles_rad.reserve(ray_count);
  result.ranges_m.reserve(ray_count);
  result.ray_indices.reserve(ray_count);
  // Points go out in increasing angle whatever the sign of the increment: the correspondence
  // search relies on that order.
  const bool reversed = scan.angle_increment_rad < 0.0;
  for (std::size_t k = 0; k < ray_count; ++k) {
    const std::size_t i = reversed ? ray_count - 1 - k : k;
    const double range_m = scan.ranges_m[i];
    // NaN fails every comparison, +inf fails the upper limit; zero is "no return" on many
    // drivers even when range_min_m is 0.
    const bool in_limits = range_m >= scan.range_min_m && range_m <= scan.range_max_m;
    if (!in_limits || !std::isfinite(range_m) || range_m == 0.0) {
      continue;
    }
    if (!scan.valid.empty() && scan.valid[i] == 0) {
      continue;
    }
    const double angle_rad = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const Eigen::Vector2d direction(std::cos(angle_rad), std::sin(angle_rad));
    result.points_m.push_back(range_m * direction);
    result.directions.push_back(direction);
    result.angles_rad.push_back(angle_rad);
    result.ranges_m.push_back(range_m);
    result.ray_indices.push_back(static_cast<int>(i));
  }
  return result;
}

}  // namespace odometry_calibration
