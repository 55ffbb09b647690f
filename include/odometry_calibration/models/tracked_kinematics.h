// A tracked or skid base whose effective wheel separation depends on how tightly it turns: the
// tracks (or the skidding wheels) scrub more the tighter the turn, so the base turns as a
// differential drive of a separation that grows from gentle curves to turning on the spot.
// Per sub-interval between encoder samples, with d_L = r_L dphi_L, d_R = r_R dphi_R:
//   nu = |d_R - d_L| / (|d_L| + |d_R|)   (0 straight, 1 on the spot; nu = min(1, |kappa| b / 2)
//                                          for curvature kappa),
//   b(nu) = b0 + b1 nu,  dtheta = (d_R - d_L) / b(nu),  chord as the differential drive's.
// b1 = 0 is the differential drive (diff_drive_kinematics.h).
#pragma once

#include <vector>

#include "odometry_calibration/models/diff_drive_kinematics.h"

namespace odometry_calibration {

/// Indices into the 4-vector of intrinsic parameters.
enum TrackedParameterIndex
{
  kTrackedLeftRadius = 0,        ///< r_L [m]
  kTrackedRightRadius = 1,       ///< r_R [m]
  kTrackedSeparation = 2,        ///< b0: the separation driving straight [m]
  kTrackedSeparationGrowth = 3,  ///< b1: how much wider on the spot [m]
  kTrackedParameterCount         ///< 4
};

/// The turn's tightness nu of wheel distances `left`, `right` (0 when neither moved).
template <typename T>
T turnTightness(const T& left, const T& right)
{
  using std::abs;
  const T sum = abs(left) + abs(right);
  if (sum < T(1e-12))
    return T(0.0);
  return abs(right - left) / sum;
}

/// Base motion of one sub-interval from the wheels' tick increments.
template <typename T>
Pose2T<T> trackedStep(const T* intrinsic, double ticks_left, double ticks_right,
                      double ticks_per_turn)
{
  using std::cos;
  using std::sin;
  const double to_rad = 2.0 * M_PI / ticks_per_turn;
  const T left_m = intrinsic[kTrackedLeftRadius] * T(ticks_left * to_rad);
  const T right_m = intrinsic[kTrackedRightRadius] * T(ticks_right * to_rad);
  const T separation = intrinsic[kTrackedSeparation] +
                       intrinsic[kTrackedSeparationGrowth] * turnTightness(left_m, right_m);
  const T dtheta = (right_m - left_m) / separation;
  const T chord = (left_m + right_m) / T(2.0) * sinc(dtheta / T(2.0));
  return Pose2T<T>(chord * cos(dtheta / T(2.0)), chord * sin(dtheta / T(2.0)), dtheta);
}

/// The tracked base as a kinematic model for fitSensorMotion (intrinsics r_L, r_R, b0, b1).
struct TrackedKinematics
{
  using Layout = DiffDriveEncoderLayout;
  static constexpr int kIntrinsics = kTrackedParameterCount;
  template <typename T>
  static Pose2T<T> integrate(const T* intrinsic, const Layout& layout,
                             const std::vector<EncoderSample>& samples)
  {
    return composeEncoderSteps<T>(
        samples, [&](const EncoderSample& previous, const EncoderSample& current) {
          return trackedStep(
              intrinsic, current.values(layout.left_index) - previous.values(layout.left_index),
              current.values(layout.right_index) - previous.values(layout.right_index),
              layout.ticks_per_turn);
        });
  }
};

}  // namespace odometry_calibration
