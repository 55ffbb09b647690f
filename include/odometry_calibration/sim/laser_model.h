// The simulated 2D laser's ray model: what one scan reads in a world, with the sensor effects of
// a real scanner switched on by LaserOptions (all off by default, so that a scenario without
// them reads exactly what it read before):
//
// - sweep: the rays are taken one after the other while the robot moves, ray i at
//   tau_i = i * time_increment after the stamp (sensor_msgs/LaserScan's convention), each from
//   the laser's pose at that instant; time_increment = |angle increment| / (2 pi rate), a mirror
//   turning once per scan period (Hokuyo URG-04LX: 0.1 s / 1024 steps);
// - range noise growing with the range, sigma = a + b r (a = range_noise_m, b =
//   range_noise_per_m; e.g. the URG's 1 % of the range beyond 1 m);
// - that noise correlated between neighbouring rays (range_noise_correlation rho: an AR(1)
//   chain along the scan with the same sigma per ray, correlation rho^k k rays apart);
// - returns quantised to range_resolution_m (1 mm for the URG's integer millimetres);
// - mixed pixels: a beam whose footprint (max(beam divergence, ray increment) wide) straddles a
//   depth step (its two edges on different walls that do not meet at a corner, more than 3 cm
//   apart in range) returns, with
//   mixed_pixel_probability, a range drawn uniformly between the two surfaces, as a
//   phase-measuring scanner does (Tang et al., "Characterizing the URG-04LX", 2009; Ye &
//   Borenstein, "Characterization of a 2D laser scanner for mobile robot obstacle negotiation",
//   ICRA 2002);
// - dark-surface dropouts: the echo weakens as cos(incidence) / r^2, so the chance of losing a
//   return is dark_dropout_probability * (r / r_max)^2 / cos(incidence), capped at 1;
// - a range ripple fixed to the rays: ray i reads range_ripple_m * sin(2 pi i /
//   range_ripple_period_rays) too long, the same in every scan (a systematic error that depends
//   on the beam's angle in the scanner, not on the scene; it moves with the sensor).
//
// Randomness comes from two streams seeded by the scenario's seed: the historical one (the
// constant range noise and the dropouts, drawn exactly as before) and one for the new effects.
#pragma once

#include <functional>
#include <random>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"

namespace odometry_calibration {
namespace sim {

/// Minimum range step [m] between the two edges of a beam's footprint that counts as a depth
/// discontinuity (a mixed pixel); smaller steps are a slanted wall or a corner.
constexpr double kMixedPixelMinStepM = 0.03;

/// Measures scans of a world with the options' ray model. Deterministic for a seed.
class LaserModel
{
public:
  LaserModel(const LaserOptions& options, unsigned seed);

  /// Time between consecutive rays [s]: 0 without sweep (all rays at the stamp).
  double timeIncrement() const { return time_increment_s_; }
  /// Time from the first ray to the last [s] (0 without sweep).
  double sweepDuration() const { return time_increment_s_ * (options_.rays - 1); }

  /// One scan stamped `stamp_s`; `T_world_laser_at(tau)` is the laser's world pose tau seconds
  /// after the stamp (asked only at tau = 0 without sweep).
  ScanSample measure(const World& world, double stamp_s,
                     const std::function<Pose2(double)>& T_world_laser_at);

private:
  /// A scan stamped `stamp_s` with the sensor's angles, limits and times, its ranges unset.
  ScanSample scanHeader(double stamp_s) const;
  /// A returned ray's range [m] with the ripple and the noise: the AR(1) chain's `unit_noise`
  /// when correlated, else an independent draw (scaled with range when range_noise_per_m > 0).
  double withNoise(double range, int ray, double unit_noise);
  /// The range as the sensor reports it: NaN for a dropout (uniform, or on dark surfaces: more
  /// likely far and at grazing incidence), rounded to the resolution, +inf beyond max_range,
  /// -inf closer than min_range.
  double reported(double range, double cos_incidence);

  /// The range of one ray (before noise): the centre's hit, or a mixed pixel.
  double trueRange(const World& world, const Eigen::Vector2d& origin, double angle_rad,
                   double* cos_incidence);

  LaserOptions options_;
  double time_increment_s_ = 0.0;
  double angle_increment_rad_ = 0.0;
  std::mt19937_64 rng_;          ///< historical stream: constant noise, dropouts
  std::mt19937_64 realism_rng_;  ///< the sensor effects' stream
  std::normal_distribution<double> range_noise_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
};

}  // namespace sim
}  // namespace odometry_calibration
