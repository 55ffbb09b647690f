// Synthetic planar lidar scans for the PLICP tests and benchmarks: a ray caster over worlds made
// of segments and circles, the three worlds of issue 11 (an office room with furniture, a
// cluttered room, a long smooth corridor) and random trials (true motion, perturbed guess).
//
// Header-only test helper (shared by test/ and bench/); not part of the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/StdVector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {
namespace synthetic {

constexpr double kDegToRad = M_PI / 180.0;

/// A world: opaque segments and circles, coordinates in the world frame [m].
struct World
{
  std::string name;
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> segments;  // x0 y0 x1 y1
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> circles;   // cx cy r
  /// Sensor positions are drawn in this box [m] (x_min, y_min, x_max, y_max)...
  Eigen::Vector4d free_box = Eigen::Vector4d::Zero();
  /// ... at least this far from every obstacle [m].
  double clearance_m = 0.4;
  /// The corridor's axis (unit, world frame) when the world is a corridor, else zero.
  Eigen::Vector2d corridor_axis = Eigen::Vector2d::Zero();

  void addSegment(double x0, double y0, double x1, double y1)
  {
    segments.emplace_back(x0, y0, x1, y1);
  }
  /// Axis-aligned box [x0, x1] x [y0, y1] rotated by angle_rad about its centre.
  void addBox(double cx, double cy, double width, double depth, double angle_rad = 0.0)
  {
    const Eigen::Rotation2Dd R(angle_rad);
    const Eigen::Vector2d c(cx, cy);
    const Eigen::Vector2d corners[4] = {c + R * Eigen::Vector2d(-width / 2, -depth / 2),
                                        c + R * Eigen::Vector2d(width / 2, -depth / 2),
                                        c + R * Eigen::Vector2d(width / 2, depth / 2),
                                        c + R * Eigen::Vector2d(-width / 2, depth / 2)};
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d& a = corners[k];
      const Eigen::Vector2d& b = corners[(k + 1) % 4];
      addSegment(a.x(), a.y(), b.x(), b.y());
    }
  }
  void addCircle(double cx, double cy, double radius_m) { circles.emplace_back(cx, cy, radius_m); }
};

/// Distance from the ray origin + s * direction to the first obstacle, +inf if none.
inline double castRay(const World& world, const Eigen::Vector2d& origin,
                      const Eigen::Vector2d& direction)
{
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector4d& s : world.segments) {
    const Eigen::Vector2d a(s(0), s(1));
    const Eigen::Vector2d e(s(2) - s(0), s(3) - s(1));
    const double denominator = direction.x() * e.y() - direction.y() * e.x();
    if (std::abs(denominator) < 1e-15) {
      continue;
    }
    const Eigen::Vector2d w = a - origin;
    const double along_ray = (w.x() * e.y() - w.y() * e.x()) / denominator;
    const double along_segment = (w.x() * direction.y() - w.y() * direction.x()) / denominator;
    if (along_ray > 0.0 && along_segment >= 0.0 && along_segment <= 1.0) {
      best = std::min(best, along_ray);
    }
  }
  for (const Eigen::Vector3d& c : world.circles) {
    const Eigen::Vector2d w = origin - c.head<2>();
    const double b = w.dot(direction);
    const double discriminant = b * b - (w.squaredNorm() - c(2) * c(2));
    if (discriminant < 0.0) {
      continue;
    }
    const double root = std::sqrt(discriminant);
    const double near = -b - root;
    const double far = -b + root;
    if (near > 0.0) {
      best = std::min(best, near);
    } else if (far > 0.0) {
      best = std::min(best, far);
    }
  }
  return best;
}

/// Distance from a point to the nearest obstacle [m].
inline double clearance(const World& world, const Eigen::Vector2d& p)
{
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector4d& s : world.segments) {
    const Eigen::Vector2d a(s(0), s(1));
    const Eigen::Vector2d e(s(2) - s(0), s(3) - s(1));
    const double u = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + u * e - p).norm());
  }
  for (const Eigen::Vector3d& c : world.circles) {
    best = std::min(best, std::abs((p - c.head<2>()).norm() - c(2)));
  }
  return best;
}

/// The lidar: ray count over a field of view, range limits, Gaussian range noise.
struct LidarModel
{
  int ray_count = 682;
  double field_of_view_rad = 240.0 * kDegToRad;
  double range_max_m = 20.0;
  double range_min_m = 0.02;
  double range_sigma_m = 0.01;
};

/// A scan of `world` from sensor pose T_world_sensor; beyond range_max a ray reads +inf.
template <typename Rng>
Scan simulateScan(const World& world, const Pose2& T_world_sensor, const LidarModel& lidar,
                  Rng& rng)
{
  Scan scan;
  scan.angle_min_rad = -0.5 * lidar.field_of_view_rad;
  scan.angle_increment_rad = lidar.field_of_view_rad / (lidar.ray_count - 1);
  scan.range_min_m = lidar.range_min_m;
  scan.range_max_m = lidar.range_max_m;
  // Always draw the noise, so that a noise-free lidar sees the same trials as a noisy one.
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Vector2d origin(T_world_sensor.x(), T_world_sensor.y());
  for (int i = 0; i < lidar.ray_count; ++i) {
    const double angle = T_world_sensor.theta() + scan.angle_min_rad + i * scan.angle_increment_rad;
    const double range = castRay(world, origin, Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    const double reading = range + lidar.range_sigma_m * noise(rng);
    scan.ranges_m.push_back(range <= lidar.range_max_m ? reading
                                                       : std::numeric_limits<double>::infinity());
  }
  return scan;
}

/// An office room, 8 m x 6 m: a door recess, desks along the walls, a cabinet, a bookshelf at an
/// angle, a round pillar and a table in the middle area.
inline World officeRoom()
{
  World world;
  world.name = "office";
  // Walls with a door recess in the top wall (x 3.0-4.0, 0.3 m deep).
  world.addSegment(0, 0, 8, 0);
  world.addSegment(8, 0, 8, 6);
  world.addSegment(8, 6, 4, 6);
  world.addSegment(4, 6, 4, 6.3);
  world.addSegment(4, 6.3, 3, 6.3);
  world.addSegment(3, 6.3, 3, 6);
  world.addSegment(3, 6, 0, 6);
  world.addSegment(0, 6, 0, 0);
  world.addBox(1.6, 0.45, 1.6, 0.8);        // desk along the bottom wall
  world.addBox(6.6, 5.55, 2.0, 0.8);        // desk along the top wall
  world.addBox(7.7, 2.0, 0.6, 1.2);         // cabinet on the right wall
  world.addBox(0.35, 4.2, 0.5, 1.6, 0.15);  // bookshelf, slightly turned
  world.addBox(4.8, 1.2, 1.2, 0.7, 0.3);    // small table
  world.addCircle(5.6, 3.6, 0.25);          // pillar
  world.addCircle(2.2, 4.6, 0.03);          // chair legs
  world.addCircle(2.6, 4.6, 0.03);
  world.addCircle(2.2, 5.0, 0.03);
  world.addCircle(2.6, 5.0, 0.03);
  world.free_box = Eigen::Vector4d(1.5, 1.6, 6.5, 4.6);
  return world;
}

/// A cluttered room, 10 m x 8 m, with boxes and cylinders of random sizes and orientations
/// scattered around a free area in the middle (fixed seed: the same room every time).
inline World clutteredRoom()
{
  World world;
  world.name = "cluttered";
  world.addSegment(0, 0, 10, 0);
  world.addSegment(10, 0, 10, 8);
  world.addSegment(10, 8, 0, 8);
  world.addSegment(0, 8, 0, 0);
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> x(0.5, 9.5), y(0.5, 7.5), size(0.15, 0.8),
      angle(-M_PI, M_PI), radius(0.05, 0.3);
  int placed = 0;
  while (placed < 28) {
    const Eigen::Vector2d c(x(rng), y(rng));
    // Keep the robot's area (around the room's centre) open.
    if (std::abs(c.x() - 5.0) < 2.0 && std::abs(c.y() - 4.0) < 1.5) {
      continue;
    }
    if (placed % 3 == 2) {
      world.addCircle(c.x(), c.y(), radius(rng));
    } else {
      world.addBox(c.x(), c.y(), size(rng), size(rng), angle(rng));
    }
    ++placed;
  }
  world.free_box = Eigen::Vector4d(3.6, 3.0, 6.4, 5.0);
  return world;
}

/// A smooth corridor 2 m wide and 200 m long: its ends are far beyond the lidar's range.
inline World corridor()
{
  World world;
  world.name = "corridor";
  world.addSegment(-100, 0, 100, 0);
  world.addSegment(-100, 2, 100, 2);
  world.free_box = Eigen::Vector4d(-5.0, 0.6, 5.0, 1.4);
  world.clearance_m = 0.3;
  world.corridor_axis = Eigen::Vector2d::UnitX();
  return world;
}

/// One test case: two scans, the true motion between them and an initial guess.
struct Trial
{
  Pose2 T_world_ref;    ///< reference sensor pose in the world
  Pose2 T_ref_new;      ///< true motion: new sensor pose in the reference sensor frame
  Pose2 guess_ref_new;  ///< initial guess: the truth perturbed
  Scan reference;
  Scan current;
};

/// Draws a trial: a free reference pose with random heading, a motion up to max_translation_m
/// and max_rotation_rad, and a guess off by [guess_min_m, guess_max_m] and
/// [guess_min_rad, guess_max_rad] in random directions.
struct TrialOptions
{
  double max_translation_m = 0.3;
  double max_rotation_rad = 15.0 * kDegToRad;
  double guess_min_m = 0.02;
  double guess_max_m = 0.05;
  double guess_min_rad = 1.0 * kDegToRad;
  double guess_max_rad = 3.0 * kDegToRad;
};

template <typename Rng>
Trial makeTrial(const World& world, const LidarModel& lidar, const TrialOptions& options, Rng& rng)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  auto inBox = [&]() {
    return Eigen::Vector2d(world.free_box(0) + unit(rng) * (world.free_box(2) - world.free_box(0)),
                           world.free_box(1) + unit(rng) * (world.free_box(3) - world.free_box(1)));
  };
  Trial trial;
  for (;;) {
    const Eigen::Vector2d start = inBox();
    if (clearance(world, start) < world.clearance_m) {
      continue;
    }
    trial.T_world_ref = Pose2(start.x(), start.y(), heading(rng));
    const double distance = options.max_translation_m * unit(rng);
    const double direction = heading(rng);
    const double rotation = options.max_rotation_rad * (2.0 * unit(rng) - 1.0);
    trial.T_ref_new =
        Pose2(distance * std::cos(direction), distance * std::sin(direction), rotation);
    const Pose2 T_world_new = trial.T_world_ref * trial.T_ref_new;
    if (clearance(world, Eigen::Vector2d(T_world_new.x(), T_world_new.y())) >= world.clearance_m) {
      break;
    }
  }
  const double off_m =
      options.guess_min_m + (options.guess_max_m - options.guess_min_m) * unit(rng);
  const double off_direction = heading(rng);
  const double off_rad =
      (options.guess_min_rad + (options.guess_max_rad - options.guess_min_rad) * unit(rng)) *
      (unit(rng) < 0.5 ? -1.0 : 1.0);
  trial.guess_ref_new = Pose2(trial.T_ref_new.x() + off_m * std::cos(off_direction),
                              trial.T_ref_new.y() + off_m * std::sin(off_direction),
                              trial.T_ref_new.theta() + off_rad);
  trial.reference = simulateScan(world, trial.T_world_ref, lidar, rng);
  trial.current = simulateScan(world, trial.T_world_ref * trial.T_ref_new, lidar, rng);
  return trial;
}

}  // namespace synthetic
}  // namespace odometry_calibration
