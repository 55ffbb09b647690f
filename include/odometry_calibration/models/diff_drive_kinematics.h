// Differential-drive kinematics (the paper's CMLE baseline: Censi, Franchi, Marchionni,
// Oriolo, "Simultaneous calibration of odometry and sensor parameters for mobile robots",
// T-RO 2013), templated for Ceres autodiff.
//
// Between consecutive encoder samples the wheels turn by dphi_L, dphi_R [rad]; with constant
// wheel velocities over that sub-interval the robot moves on an arc:
//   d_L = r_L dphi_L,  d_R = r_R dphi_R,  v = (d_L + d_R) / 2,  dtheta = (d_R - d_L) / b,
//   chord = v sinc(dtheta / 2) in the direction dtheta / 2 (exact).
#pragma once

#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/encoder_steps.h"  // sinc, composeEncoderSteps

namespace odometry_calibration {

/// Where the wheel encoders are in an EncoderSample and their resolution.
struct DiffDriveEncoderLayout
{
  int left_index = 0;              ///< cumulative ticks of the left wheel
  int right_index = 1;             ///< cumulative ticks of the right wheel
  double ticks_per_turn = 2000.0;  ///< encoder ticks per wheel revolution
};

/// Indices into the 3-vector of intrinsic parameters.
enum DiffDriveParameterIndex
{
  kLeftRadius = 0,          ///< r_L [m]
  kRightRadius = 1,         ///< r_R [m]
  kWheelSeparation = 2,     ///< b [m]
  kDiffDriveParameterCount  ///< 3
};

/// Base motion of one sub-interval from the wheels' tick increments.
template <typename T>
Pose2T<T> diffDriveStep(const T* intrinsic, double ticks_left, double ticks_right,
                        double ticks_per_turn)
{
  using std::cos;
  using std::sin;
  const double to_rad = 2.0 * M_PI / ticks_per_turn;
  const T left_m = intrinsic[kLeftRadius] * T(ticks_left * to_rad);
  const T right_m = intrinsic[kRightRadius] * T(ticks_right * to_rad);
  const T dtheta = (right_m - left_m) / intrinsic[kWheelSeparation];
  const T chord = (left_m + right_m) / T(2.0) * sinc(dtheta / T(2.0));
  return Pose2T<T>(chord * cos(dtheta / T(2.0)), chord * sin(dtheta / T(2.0)), dtheta);
}

/// Base motion from the first to the last sample: the composition of all sub-intervals.
template <typename T>
Pose2T<T> integrateDiffDriveMotion(const T* intrinsic, const DiffDriveEncoderLayout& layout,
                                   const std::vector<EncoderSample>& samples)
{
  return composeEncoderSteps<T>(
      samples, [&](const EncoderSample& previous, const EncoderSample& current) {
        return diffDriveStep(
            intrinsic, current.values(layout.left_index) - previous.values(layout.left_index),
            current.values(layout.right_index) - previous.values(layout.right_index),
            layout.ticks_per_turn);
      });
}

}  // namespace odometry_calibration

namespace odometry_calibration {

/// The differential drive as a kinematic model for fitSensorMotion (intrinsics r_L, r_R, b).
struct DiffDriveKinematics
{
  using Layout = DiffDriveEncoderLayout;
  static constexpr int kIntrinsics = kDiffDriveParameterCount;
  template <typename T>
  static Pose2T<T> integrate(const T* intrinsic, const Layout& layout,
                             const std::vector<EncoderSample>& samples)
  {
    return integrateDiffDriveMotion(intrinsic, layout, samples);
  }
};

}  // namespace odometry_calibration
