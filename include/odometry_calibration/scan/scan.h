// A planar laser scan (ranges on equally spaced rays) and its conversion to Cartesian points.
//
// The scan mirrors sensor_msgs/LaserScan without depending on ROS: ray i points at
// angle_min_rad + i * angle_increment_rad in the sensor frame (x forward, y left, counter-clockwise
// positive, REP 103) and measured ranges_m[i]. Readings that are NaN, infinite, zero, outside
// [range_min_m, range_max_m] or marked invalid are dropped when the scan turns into points.
//
// A spinning lidar measures its rays one after the other (ray i at i * time_increment_s after
// the stamp, as in sensor_msgs/LaserScan); when the sensor moves during the sweep, each point is
// seen from a different pose. Given the sensor's velocity, scanToPoints() moves every point into
// the frame of the sensor at the stamp (the velocity, and optionally its constant rate of change,
// integrated over the ray's time: the SE(2) exponential exp(tau v + tau^2 / 2 a)), so that the
// scan is the picture of one pose.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

namespace odometry_calibration {

/// One planar range scan in the sensor's own frame.
struct Scan
{
  double angle_min_rad = 0.0;        ///< angle of ray 0 [rad]
  double angle_increment_rad = 0.0;  ///< angle between consecutive rays [rad], != 0
  double range_min_m = 0.0;          ///< readings below this are not returns [m]
  double range_max_m = 0.0;          ///< readings above this are not returns [m]
  std::vector<double> ranges_m;      ///< one reading per ray [m]
  /// Optional per-ray validity (1 = usable); empty means "all rays usable". When not empty it
  /// must have one entry per ray (e.g. to mask the sensor's housing).
  std::vector<std::uint8_t> valid;
  /// Time between consecutive rays [s] (sensor_msgs/LaserScan time_increment): ray i is measured
  /// i * time_increment_s after the stamp. 0 means all rays at the stamp (no motion compensation).
  double time_increment_s = 0.0;
  /// Optional per-ray times after the stamp [s], one per ray, replacing i * time_increment_s
  /// (e.g. a scan made from a 3D lidar's cloud, cloud_to_scan.h, whose rays are not taken at
  /// equal intervals). Empty: the times come from time_increment_s.
  std::vector<double> ray_times_s;
  /// Optional per-ray bearings [rad], one per ray, non-decreasing, replacing angle_min_rad +
  /// i * angle_increment_rad (then only a nominal spacing, > 0): a scan of points not on equally
  /// spaced rays, e.g. a 3D lidar's in-band points ordered by bearing (cloud_to_scan.h,
  /// `scan_from: points`). Empty: the rays are equally spaced.
  std::vector<double> ray_angles_rad;
};

/// Velocity of the sensor during a scan's sweep, in the sensor's frame at the stamp: at the stamp
/// [m/s, m/s, rad/s] and its rate of change, constant over the sweep [m/s^2, m/s^2, rad/s^2; 0: a
/// constant velocity]. The sensor's pose tau seconds after the stamp is exp(tau v + tau^2 / 2 a)
/// (the twist integrated in the stamp's frame: exact for a constant velocity, second order in the
/// motion otherwise). E.g. odometry's motion over the last interval divided by its duration.
struct SensorVelocity
{
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double omega_radps = 0.0;
  double ax_mps2 = 0.0;
  double ay_mps2 = 0.0;
  double alpha_radps2 = 0.0;

  bool isZero() const
  {
    return vx_mps == 0.0 && vy_mps == 0.0 && omega_radps == 0.0 && ax_mps2 == 0.0 &&
           ay_mps2 == 0.0 && alpha_radps2 == 0.0;
  }
};

/// Throws std::invalid_argument naming the offending field when the scan's geometry is unusable
/// (angle_increment_rad zero or not finite, range limits not 0 <= min < max, a validity mask of
/// the wrong length, time_increment_s not finite, ray_times_s of the wrong length or not finite,
/// ray_angles_rad of the wrong length, not finite, decreasing or beyond [-4 pi, 4 pi], or with a
/// negative angle_increment_rad).
/// Readings themselves are never rejected: bad ones are dropped by scanToPoints().
void validate(const Scan& scan);

/// The usable readings of a scan as points in the sensor frame, ordered by increasing ray angle
/// (reverse ray order when angle_increment_rad < 0). All vectors have the same length. With
/// motion compensation, everything is as seen from the sensor's pose at the stamp: the points,
/// their bearings (angles_rad, directions; ordered by bearing) and their distances (ranges_m).
struct ScanPoints
{
  /// Points (x, y) in the sensor frame [m].
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> points_m;
  /// Unit ray directions (cos, sin) of each point's ray: the direction along which its range
  /// noise acts (Censi ICRA 2007, the readings z are the ranges). With motion compensation, the
  /// bearing of the compensated point (the ray turned by the sweep's few milliradians at most).
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> directions;
  std::vector<double> angles_rad;  ///< ray angle of each point [rad]
  std::vector<double> ranges_m;    ///< range of each point [m]
  std::vector<int> ray_indices;    ///< index of each point's ray in Scan::ranges_m

  std::size_t size() const { return points_m.size(); }
  bool empty() const { return points_m.empty(); }
};

/// Whether the scan's rays carry times (time_increment_s or ray_times_s), so that the motion
/// during its sweep can be compensated.
bool hasRayTimes(const Scan& scan);

/// How long the sweep lasts: the latest ray time after the stamp [s] (0 without ray times).
double sweepDuration(const Scan& scan);

/// Whether reading i is usable: finite, non-zero, within [range_min_m, range_max_m] and not
/// masked out by `valid`. Expects a validated scan and i < ranges_m.size(). Inline: it runs for
/// every ray of every scan, twice (countUsableReadings, scanToPoints).
inline bool isUsableReading(const Scan& scan, std::size_t i)
{
  const double range_m = scan.ranges_m[i];
  // NaN fails every comparison, +inf fails the upper limit; zero is "no return" on many
  // drivers even when range_min_m is 0.
  const bool in_limits = range_m >= scan.range_min_m && range_m <= scan.range_max_m;
  return in_limits && std::isfinite(range_m) && range_m != 0.0 &&
         (scan.valid.empty() || scan.valid[i] != 0);
}

/// How many readings are usable (what scanToPoints would keep), without converting them.
std::size_t countUsableReadings(const Scan& scan);

/// Converts the usable readings of `scan` to points: drops NaN, +-inf, zero, below range_min_m,
/// above range_max_m and masked-out readings. Throws std::invalid_argument (via validate) only
/// for an unusable scan geometry; a scan with no usable reading gives an empty ScanPoints.
/// When `velocity` is not zero and the rays carry times (hasRayTimes), compensates the motion
/// during the sweep: the point p of ray i becomes exp(tau_i v + tau_i^2 / 2 a) p, tau_i = i *
/// time_increment_s (or ray_times_s[i]), v and a the velocity and its rate of change (the
/// sensor's pose at tau_i in its pose at the stamp).
ScanPoints scanToPoints(const Scan& scan, const SensorVelocity& velocity = {});

}  // namespace odometry_calibration
