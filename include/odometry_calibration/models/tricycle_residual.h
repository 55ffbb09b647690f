// The tricycle's error term for one keyframe pair (docs/models.md, "The tricycle"):
// e = Z^-1 * h(X, Delta_r), h = T_bs^-1 * Delta_r * T_bs, whitened by the pair's covariance.
#pragma once

#include <vector>

#include "odometry_calibration/models/sensor_motion_fit.h"
#include "odometry_calibration/models/tricycle_kinematics.h"

namespace odometry_calibration {

/// The tricycle as a kinematic model for fitSensorMotion (intrinsics: Ks, Kt, a, ds).
struct TricycleKinematics
{
  using Layout = TricycleEncoderLayout;
  static constexpr int kIntrinsics = kTricycleParameterCount;
  template <typename T>
  static Pose2T<T> integrate(const T* intrinsic, const Layout& layout,
                             const std::vector<EncoderSample>& samples)
  {
    return integrateTricycleMotion(intrinsic, layout, samples);
  }
};

/// Cost functor for ceres::AutoDiffCostFunction<TricyclePairResidual, 3, 4, 3>.
using TricyclePairResidual = SensorMotionResidual<TricycleKinematics>;

}  // namespace odometry_calibration
