#include "odometry_calibration/sim/laser_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace odometry_calibration {
namespace sim {
namespace {

/// Whether two walls meet at an end (a corner of one surface, not a depth step).
bool joined(const Segment& a, const Segment& b)
{
  constexpr double kTolerance = 1e-9;
  for (const Eigen::Vector2d& p : {a.a, a.b}) {
    if ((p - b.a).norm() < kTolerance || (p - b.b).norm() < kTolerance)
      return true;
  }
  return false;
}

}  // namespace

LaserModel::LaserModel(const LaserOptions& options, unsigned seed)
    : options_(options),
      angle_increment_rad_(options.fov_rad / (options.rays - 1)),
      rng_(seed ^ 0x5eed5eedULL),
      realism_rng_(seed ^ 0x4ea115e5ULL),
      range_noise_(0.0, options.range_noise_m)
{
  if (options_.sweep)
    time_increment_s_ = std::abs(angle_increment_rad_) / (2.0 * M_PI * options_.rate_hz);
}

double LaserModel::trueRange(const World& world, const Eigen::Vector2d& origin, double angle_rad,
                             double* cos_incidence)
{
  const RayHit centre = world.castRayHit(origin, angle_rad, options_.max_range_m);
  *cos_incidence = centre.cos_incidence;
  if (options_.mixed_pixel_probability <= 0.0)
    return centre.range_m;
  // The beam's footprint: its two edges. A mixed pixel needs them on two different walls at
  // clearly different ranges (a depth step), both in range.
  const double half_width = 0.5 * std::max(options_.beam_divergence_rad, angle_increment_rad_);
  const RayHit left = world.castRayHit(origin, angle_rad + half_width, options_.max_range_m);
  const RayHit right = world.castRayHit(origin, angle_rad - half_width, options_.max_range_m);
  if (left.segment < 0 || right.segment < 0 || left.segment == right.segment ||
      std::abs(left.range_m - right.range_m) < kMixedPixelMinStepM ||
      joined(world.segments()[static_cast<std::size_t>(left.segment)],
             world.segments()[static_cast<std::size_t>(right.segment)])) {
    return centre.range_m;
  }
  if (unit_(realism_rng_) >= options_.mixed_pixel_probability)
    return centre.range_m;
  const double near = std::min(left.range_m, right.range_m);
  const double far = std::max(left.range_m, right.range_m);
  *cos_incidence = std::max(left.cos_incidence, right.cos_incidence);
  return near + unit_(realism_rng_) * (far - near);
}

ScanSample LaserModel::scanHeader(double stamp_s) const
{
  ScanSample scan;
  scan.stamp_s = stamp_s;
  scan.angle_min_rad = static_cast<float>(-0.5 * options_.fov_rad);
  scan.angle_increment_rad = static_cast<float>(angle_increment_rad_);
  scan.range_min_m = static_cast<float>(options_.min_range_m);
  scan.range_max_m = static_cast<float>(options_.max_range_m);
  scan.time_increment_s = time_increment_s_;
  scan.scan_time_s = 1.0 / options_.rate_hz;
  scan.ranges.resize(static_cast<std::size_t>(options_.rays));
  return scan;
}

double LaserModel::withNoise(double range, int ray, double unit_noise)
{
  if (options_.range_ripple_m > 0.0)
    range +=
        options_.range_ripple_m * std::sin(2.0 * M_PI * ray / options_.range_ripple_period_rays);
  if (options_.range_noise_correlation > 0.0) {
    range += (options_.range_noise_m + options_.range_noise_per_m * range) * unit_noise;
  } else if (options_.range_noise_per_m > 0.0) {
    range +=
        (options_.range_noise_m + options_.range_noise_per_m * range) * unit_normal_(realism_rng_);
  } else if (options_.range_noise_m > 0.0) {
    range += range_noise_(rng_);
  }
  return range;
}

double LaserModel::reported(double range, double cos_incidence)
{
  bool dropout = options_.dropout_probability > 0.0 && unit_(rng_) < options_.dropout_probability;
  if (!dropout && std::isfinite(range) && options_.dark_dropout_probability > 0.0) {
    const double relative = range / options_.max_range_m;
    const double chance =
        options_.dark_dropout_probability * relative * relative / std::max(cos_incidence, 1e-6);
    dropout = unit_(realism_rng_) < std::min(chance, 1.0);
  }
  if (std::isfinite(range) && options_.range_resolution_m > 0.0)
    range = std::round(range / options_.range_resolution_m) * options_.range_resolution_m;
  if (dropout) {
    return std::numeric_limits<double>::quiet_NaN();
  } else if (range > options_.max_range_m) {
    return std::numeric_limits<double>::infinity();
  } else if (range < options_.min_range_m) {
    return -std::numeric_limits<double>::infinity();
  }
  return range;
}

ScanSample LaserModel::measure(const World& world, double stamp_s,
                               const std::function<Pose2(double)>& T_world_laser_at)
{
  ScanSample scan = scanHeader(stamp_s);
  const float angle_min = scan.angle_min_rad;
  Pose2 T_world_laser = T_world_laser_at(0.0);
  const double rho = options_.range_noise_correlation;
  const double innovation_scale = std::sqrt(1.0 - rho * rho);
  double unit_noise = 0.0;  // the AR(1) chain along the scan, unit variance
  bool chain_started = false;
  for (int i = 0; i < options_.rays; ++i) {
    if (options_.sweep && i > 0)
      T_world_laser = T_world_laser_at(i * time_increment_s_);
    const Eigen::Vector2d origin(T_world_laser.x(), T_world_laser.y());
    const double angle =
        T_world_laser.theta() + angle_min + i * options_.fov_rad / (options_.rays - 1);
    double cos_incidence = 1.0;
    double range = trueRange(world, origin, angle, &cos_incidence);
    if (rho > 0.0) {  // the chain moves on at every ray, returned or not: rho^k k rays apart
      const double z = unit_normal_(realism_rng_);
      unit_noise = chain_started ? rho * unit_noise + innovation_scale * z : z;
      chain_started = true;
    }
    if (std::isfinite(range))
      range = withNoise(range, i, unit_noise);
    scan.ranges[static_cast<std::size_t>(i)] = static_cast<float>(reported(range, cos_incidence));
  }
  return scan;
}

}  // namespace sim
}  // namespace odometry_calibration
