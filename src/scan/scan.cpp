#include "odometry_calibration/scan/scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {
namespace {

/// The sensor's pose after moving for tau_s seconds with `velocity` (and its rate of change):
/// the SE(2) exponential exp(tau v + tau^2 / 2 a) as se2Exp computes it, with the cosine and sine
/// of its heading
/// (*cos_theta, *sin_theta) from the same evaluation (once per point of every scan).
Pose2 poseAfter(const SensorVelocity& velocity, double tau_s, double* cos_theta, double* sin_theta)
{
  const double half_tau2 = 0.5 * tau_s * tau_s;
  const Eigen::Vector3d xi(velocity.vx_mps * tau_s + velocity.ax_mps2 * half_tau2,
                           velocity.vy_mps * tau_s + velocity.ay_mps2 * half_tau2,
                           velocity.omega_radps * tau_s + velocity.alpha_radps2 * half_tau2);
  const double theta = xi.z();
  *cos_theta = std::cos(theta);
  *sin_theta = std::sin(theta);
  double a = 1.0;  // sin(theta) / theta
  double b = 0.0;  // (1 - cos(theta)) / theta
  if (std::abs(theta) > 1e-9) {
    a = *sin_theta / theta;
    b = (1.0 - *cos_theta) / theta;
  } else {
    b = 0.5 * theta;
  }
  return Pose2(a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y(), theta);
}

/// Moves every point into the frame of the sensor at the stamp and reorders by bearing (the
/// compensation can swap neighbours across a depth discontinuity).
void compensateSweep(const Scan& scan, const SensorVelocity& velocity, ScanPoints& points)
{
  const std::size_t n = points.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t ray = static_cast<std::size_t>(points.ray_indices[k]);
    const double tau_s = scan.ray_times_s.empty() ? static_cast<double>(ray) * scan.time_increment_s
                                                  : scan.ray_times_s[ray];
    double c = 1.0;
    double s = 0.0;
    const Pose2 T_stamp_ray = poseAfter(velocity, tau_s, &c, &s);
    const Eigen::Vector2d& p = points.points_m[k];
    const Eigen::Vector2d q(c * p.x() - s * p.y() + T_stamp_ray.x(),
                            s * p.x() + c * p.y() + T_stamp_ray.y());
    points.points_m[k] = q;
    points.ranges_m[k] = q.norm();
    points.directions[k] = q / points.ranges_m[k];
    // The bearing moves by little: keep the ray angles' unwrapping (e.g. beyond pi).
    points.angles_rad[k] += normalizeAngle(std::atan2(q.y(), q.x()) - points.angles_rad[k]);
  }
  if (std::is_sorted(points.angles_rad.begin(), points.angles_rad.end())) {
    return;
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return points.angles_rad[i] < points.angles_rad[j];
  });
  ScanPoints sorted;
  for (const std::size_t k : order) {
    sorted.points_m.push_back(points.points_m[k]);
    sorted.directions.push_back(points.directions[k]);
    sorted.angles_rad.push_back(points.angles_rad[k]);
    sorted.ranges_m.push_back(points.ranges_m[k]);
    sorted.ray_indices.push_back(points.ray_indices[k]);
  }
  points = std::move(sorted);
}

/// Unit directions (cos, sin) of the rays of scans with this geometry: ray i at angle_min_rad +
/// i * angle_increment_rad. Kept per thread for the last geometry asked for (a lidar's scans
/// all share one), since the trigonometry is a tenth of a small scan's match otherwise.
const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& rayDirections(
    double angle_min_rad, double angle_increment_rad, std::size_t ray_count)
{
  struct Table
  {
    double angle_min_rad = std::numeric_limits<double>::quiet_NaN();
    double angle_increment_rad = std::numeric_limits<double>::quiet_NaN();
    std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> directions;
  };
  thread_local Table table;
  if (table.angle_min_rad != angle_min_rad || table.angle_increment_rad != angle_increment_rad ||
      table.directions.size() != ray_count) {
    table.angle_min_rad = angle_min_rad;
    table.angle_increment_rad = angle_increment_rad;
    table.directions.resize(ray_count);
    for (std::size_t i = 0; i < ray_count; ++i) {
      const double angle_rad = angle_min_rad + static_cast<double>(i) * angle_increment_rad;
      table.directions[i] = Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad));
    }
  }
  return table.directions;
}

/// The nominal angles: a non-zero increment, every ray within two turns either way.
void validateAngles(const Scan& scan)
{
  if (!std::isfinite(scan.angle_increment_rad) || scan.angle_increment_rad == 0.0) {
    throw std::invalid_argument("scan angle_increment_rad must be a non-zero number of radians");
  }
  if (!std::isfinite(scan.angle_min_rad)) {
    throw std::invalid_argument("scan angle_min_rad must be a finite number of radians");
  }
  // Rays beyond two turns either way are no laser's (and would make every bearing search wrap
  // angles turn by turn).
  const double last_rad =
      scan.angle_min_rad + scan.angle_increment_rad * static_cast<double>(scan.ranges_m.size());
  if (std::abs(scan.angle_min_rad) > 4.0 * M_PI || !(std::abs(last_rad) <= 4.0 * M_PI)) {
    throw std::invalid_argument("scan angles must lie within [-4 pi, 4 pi] rad: angle_min_rad " +
                                std::to_string(scan.angle_min_rad) + ", last ray at " +
                                std::to_string(last_rad));
  }
}

/// The per-ray times, if any: one finite time per ray.
void validateRayTimes(const Scan& scan)
{
  if (scan.ray_times_s.empty()) {
    return;
  }
  if (scan.ray_times_s.size() != scan.ranges_m.size()) {
    throw std::invalid_argument("scan ray_times_s has " + std::to_string(scan.ray_times_s.size()) +
                                " entries for " + std::to_string(scan.ranges_m.size()) +
                                " rays: give one per ray, or leave it empty");
  }
  for (const double t : scan.ray_times_s) {
    if (!std::isfinite(t))
      throw std::invalid_argument("scan ray_times_s must be finite numbers of seconds");
  }
}

/// The per-ray angles, if any: one per ray, within two turns, non-decreasing, with a positive
/// nominal increment.
void validateRayAngles(const Scan& scan)
{
  if (scan.ray_angles_rad.empty()) {
    return;
  }
  if (scan.ray_angles_rad.size() != scan.ranges_m.size()) {
    throw std::invalid_argument(
        "scan ray_angles_rad has " + std::to_string(scan.ray_angles_rad.size()) + " entries for " +
        std::to_string(scan.ranges_m.size()) + " rays: give one per ray, or leave it empty");
  }
  if (scan.angle_increment_rad < 0.0) {
    throw std::invalid_argument(
        "scan with ray_angles_rad needs a positive (nominal) angle_increment_rad");
  }
  for (std::size_t i = 0; i < scan.ray_angles_rad.size(); ++i) {
    const double angle = scan.ray_angles_rad[i];
    if (!(std::abs(angle) <= 4.0 * M_PI) || (i > 0 && angle < scan.ray_angles_rad[i - 1])) {
      throw std::invalid_argument(
          "scan ray_angles_rad must be finite, within [-4 pi, 4 pi] rad and non-decreasing "
          "(ray " +
          std::to_string(i) + ": " + std::to_string(angle) + ")");
    }
  }
}

}  // namespace

void validate(const Scan& scan)
{
  validateAngles(scan);
  if (!std::isfinite(scan.range_min_m) || scan.range_min_m < 0.0) {
    throw std::invalid_argument("scan range_min_m must be a finite number of metres >= 0");
  }
  // range_max may be +inf (no upper limit) but must exceed range_min.
  if (std::isnan(scan.range_max_m) || !(scan.range_max_m > scan.range_min_m)) {
    throw std::invalid_argument("scan range_max_m must be larger than range_min_m");
  }
  if (!std::isfinite(scan.time_increment_s)) {
    throw std::invalid_argument("scan time_increment_s must be a finite number of seconds");
  }
  validateRayTimes(scan);
  validateRayAngles(scan);
  if (!scan.valid.empty() && scan.valid.size() != scan.ranges_m.size()) {
    throw std::invalid_argument("scan valid mask has " + std::to_string(scan.valid.size()) +
                                " entries for " + std::to_string(scan.ranges_m.size()) +
                                " rays: give one per ray, or leave it empty");
  }
}

bool hasRayTimes(const Scan& scan)
{
  return scan.time_increment_s != 0.0 || !scan.ray_times_s.empty();
}

double sweepDuration(const Scan& scan)
{
  if (!scan.ray_times_s.empty())
    return std::max(0.0, *std::max_element(scan.ray_times_s.begin(), scan.ray_times_s.end()));
  if (scan.ranges_m.empty())
    return 0.0;
  return std::max(0.0, static_cast<double>(scan.ranges_m.size() - 1) * scan.time_increment_s);
}

std::size_t countUsableReadings(const Scan& scan)
{
  std::size_t count = 0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i)
    count += isUsableReading(scan, i) ? 1 : 0;
  return count;
}

ScanPoints scanToPoints(const Scan& scan, const SensorVelocity& velocity)
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
  // Rays at regular bearings take their directions from the cached table; a scan with its own
  // bearings (ray_angles_rad) computes them.
  const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>* directions =
      scan.ray_angles_rad.empty()
          ? &rayDirections(scan.angle_min_rad, scan.angle_increment_rad, ray_count)
          : nullptr;
  for (std::size_t k = 0; k < ray_count; ++k) {
    const std::size_t i = reversed ? ray_count - 1 - k : k;
    if (!isUsableReading(scan, i)) {
      continue;
    }
    const double range_m = scan.ranges_m[i];
    double angle_rad = 0.0;
    Eigen::Vector2d direction;
    if (scan.ray_angles_rad.empty()) {
      angle_rad = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
      direction = (*directions)[i];
    } else {
      angle_rad = scan.ray_angles_rad[i];
      direction = Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad));
    }
    result.points_m.push_back(range_m * direction);
    result.directions.push_back(direction);
    result.angles_rad.push_back(angle_rad);
    result.ranges_m.push_back(range_m);
    result.ray_indices.push_back(static_cast<int>(i));
  }
  if (!velocity.isZero() && hasRayTimes(scan)) {
    compensateSweep(scan, velocity, result);
  }
  return result;
}

}  // namespace odometry_calibration
