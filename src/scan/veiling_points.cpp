#include "odometry_calibration/scan/veiling_points.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace odometry_calibration {

std::vector<std::uint8_t> findVeilingPoints(const ScanPoints& points, double min_angle_rad,
                                            int max_ray_gap)
{
  if (!(min_angle_rad >= 0.0 && min_angle_rad < 0.5 * M_PI)) {
    throw std::invalid_argument("findVeilingPoints: min_angle_rad must be in [0, pi/2)");
  }
  if (max_ray_gap < 1) {
    throw std::invalid_argument("findVeilingPoints: max_ray_gap must be at least 1");
  }
  const std::size_t n = points.size();
  std::vector<std::uint8_t> veiling(n, 0);
  const double sin_min = std::sin(min_angle_rad);
  for (std::size_t k = 1; k < n; ++k) {
    if (std::abs(points.ray_indices[k] - points.ray_indices[k - 1]) > max_ray_gap) {
      continue;
    }
    const bool first_nearer = points.ranges_m[k - 1] <= points.ranges_m[k];
    const std::size_t near = first_nearer ? k - 1 : k;
    const std::size_t far = first_nearer ? k : k - 1;
    const Eigen::Vector2d& p = points.points_m[near];
    const Eigen::Vector2d segment = points.points_m[far] - p;
    // |sin| of the angle between the near point's ray and the segment to the far point.
    const double cross = std::abs(p.x() * segment.y() - p.y() * segment.x());
    if (cross < sin_min * p.norm() * segment.norm()) {
      veiling[far] = 1;
    }
  }
  return veiling;
}

ScanPoints removePoints(const ScanPoints& points, const std::vector<std::uint8_t>& remove)
{
  if (remove.size() != points.size()) {
    throw std::invalid_argument("removePoints: the mask must have one entry per point");
  }
  ScanPoints kept;
  kept.points_m.reserve(points.size());
  kept.directions.reserve(points.size());
  kept.angles_rad.reserve(points.size());
  kept.ranges_m.reserve(points.size());
  kept.ray_indices.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (remove[i] != 0) {
      continue;
    }
    kept.points_m.push_back(points.points_m[i]);
    kept.directions.push_back(points.directions[i]);
    kept.angles_rad.push_back(points.angles_rad[i]);
    kept.ranges_m.push_back(points.ranges_m[i]);
    kept.ray_indices.push_back(points.ray_indices[i]);
  }
  return kept;
}

}  // namespace odometry_calibration
