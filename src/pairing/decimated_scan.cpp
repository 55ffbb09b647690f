#include "odometry_calibration/pairing/decimated_scan.h"

#include <stdexcept>
#include <string>

namespace odometry_calibration {
namespace {

/// Entries 0, stride, 2 stride, ... of `values` (empty stays empty).
template <typename T>
std::vector<T> everyKth(const std::vector<T>& values, int stride)
{
  std::vector<T> kept;
  kept.reserve(values.size() / static_cast<std::size_t>(stride) + 1);
  for (std::size_t i = 0; i < values.size(); i += static_cast<std::size_t>(stride)) {
    kept.push_back(values[i]);
  }
  return kept;
}

}  // namespace

Scan decimateRays(const Scan& scan, int stride)
{
  if (stride < 1) {
    throw std::invalid_argument("ray decimation stride must be >= 1, got " +
                                std::to_string(stride));
  }
  if (stride == 1) {
    return scan;
  }
  Scan decimated;
  decimated.angle_min_rad = scan.angle_min_rad;
  decimated.angle_increment_rad = scan.angle_increment_rad * stride;
  decimated.range_min_m = scan.range_min_m;
  decimated.range_max_m = scan.range_max_m;
  decimated.ranges_m = everyKth(scan.ranges_m, stride);
  // Per-ray arrays of a wrong length are validate(scan)'s to report: kept as they are.
  const auto perRay = [&](const auto& values) {
    return values.size() == scan.ranges_m.size() ? everyKth(values, stride) : values;
  };
  decimated.valid = perRay(scan.valid);
  decimated.time_increment_s = scan.time_increment_s * stride;
  decimated.ray_times_s = perRay(scan.ray_times_s);
  decimated.ray_angles_rad = perRay(scan.ray_angles_rad);
  return decimated;
}

}  // namespace odometry_calibration
