// Helpers shared by the wheel-odometry kinematics (diff_drive_kinematics.h,
// tricycle_kinematics.h), templated for Ceres autodiff: between consecutive encoder samples the
// wheels move with constant velocities, so the base moves on a circular arc, and the motion over
// a window is the composition of these steps.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// sin(x)/x, with its series near 0 so that derivatives stay finite.
template <typename T>
T sinc(const T& x)
{
  using std::abs;
  using std::sin;
  if (abs(x) < T(1e-4)) {
    return T(1.0) - x * x / T(6.0);
  }
  return sin(x) / x;
}

/// Base motion from the first to the last sample, in the base frame at the first: the SE(2)
/// composition step(s_0, s_1) * step(s_1, s_2) * ... of the motions between consecutive samples,
/// where step(previous, current) returns a Pose2T<T>. The identity for fewer than two samples.
template <typename T, typename Step>
Pose2T<T> composeEncoderSteps(const std::vector<EncoderSample>& samples, const Step& step)
{
  Pose2T<T> motion;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    motion = motion * step(samples[k - 1], samples[k]);
  }
  return motion;
}

}  // namespace odometry_calibration
