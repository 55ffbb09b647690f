// Kinematics of the front-wheel-drive tricycle of the calibration seed
// (docs/models.md, "The tricycle"), templated for Ceres autodiff.
//
// One steered and driven front wheel, two passive rear wheels; base_link is the midpoint of the
// rear axle, x forward. Per encoder step k (seed, section 2):
//   d_k     = Kt * t_k / t_max               traction travel of the front wheel [m]
//   alpha_k = Ks * s_k * 2*pi / s_max + ds   steering angle [rad]
//   dtheta  = d_k * sin(alpha_k) / a         heading change [rad]
//   the rear-axle centre travels v = d_k * cos(alpha_k) along a circular arc of angle dtheta,
//   whose chord is v * sinc(dtheta/2) in the direction dtheta/2 (exact for constant steering
//   within the step; the seed's cos/sin(dtheta) form is its first-order version).
// The step's steering is the mean of its two readings (trapezoidal rule): the steering turns
// continuously between samples, and the end sample's reading alone leads the step's steering by
// half a sample period, which the time-offset search took for an offset of -5.3 ms at 25 Hz,
// -2.6 ms at 50 Hz and -1.1 ms at 100 Hz on a simulated tricycle. The seed's logs
// keep the end sample's reading (TricycleEncoderLayout::steering_at_step_end): the robot's own
// odometry does so, and the seed's published results are computed that way.
#pragma once

#include <cmath>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/encoder_steps.h"  // sinc, composeEncoderSteps

namespace odometry_calibration {

/// Where the tricycle's encoders are in an EncoderSample, and their resolution.
struct TricycleEncoderLayout
{
  int steering_index = 0;                 ///< index of the absolute steering encoder
  int traction_index = 1;                 ///< index of the incremental traction encoder
  double steering_ticks_per_turn = 8192;  ///< s_max [ticks / encoder turn]
  double traction_ticks_per_turn = 5000;  ///< t_max [ticks / wheel turn]
  /// Each step's steering: its end sample's reading (the seed's convention) if true, else the
  /// mean of its two readings.
  bool steering_at_step_end = false;
};

/// Indices into the 4-vector of kinematic parameters (the seed's X_k).
enum TricycleParameterIndex
{
  kSteeringScale = 0,      ///< Ks: steering angle per encoder angle [-]
  kTractionScale = 1,      ///< Kt: front-wheel travel per wheel turn [m/turn]
  kAxisLength = 2,         ///< a: front wheel to rear axle [m]
  kSteeringOffset = 3,     ///< ds: steering angle at zero reading [rad]
  kTricycleParameterCount  ///< 4
};

/// Base motion over one encoder step, given the step's traction ticks and steering reading
/// (see TricycleEncoderLayout::steering_at_step_end).
/// @param kinematic the four parameters (TricycleParameterIndex)
template <typename T>
Pose2T<T> tricycleStep(const T* kinematic, const TricycleEncoderLayout& layout,
                       double traction_ticks, double steering_ticks)
{
  using std::cos;
  using std::sin;
  const double kTwoPi = 2.0 * M_PI;
  const T travel_m = kinematic[kTractionScale] * T(traction_ticks / layout.traction_ticks_per_turn);
  const T steering_rad =
      kinematic[kSteeringScale] * T(steering_ticks * kTwoPi / layout.steering_ticks_per_turn) +
      kinematic[kSteeringOffset];
  const T dtheta = travel_m * sin(steering_rad) / kinematic[kAxisLength];
  const T chord = travel_m * cos(steering_rad) * sinc(dtheta / T(2.0));
  return Pose2T<T>(chord * cos(dtheta / T(2.0)), chord * sin(dtheta / T(2.0)), dtheta);
}

/// Base motion from the first to the last encoder sample: the composition of all steps
/// (seed's Delta_r), expressed in base_link at the first sample.
template <typename T>
Pose2T<T> integrateTricycleMotion(const T* kinematic, const TricycleEncoderLayout& layout,
                                  const std::vector<EncoderSample>& samples)
{
  return composeEncoderSteps<T>(
      samples, [&](const EncoderSample& previous, const EncoderSample& current) {
        const double traction_ticks =
            current.values(layout.traction_index) - previous.values(layout.traction_index);
        const double steering_ticks = layout.steering_at_step_end
                                          ? current.values(layout.steering_index)
                                          : 0.5 * (previous.values(layout.steering_index) +
                                                   current.values(layout.steering_index));
        return tricycleStep(kinematic, layout, traction_ticks, steering_ticks);
      });
}

}  // namespace odometry_calibration
