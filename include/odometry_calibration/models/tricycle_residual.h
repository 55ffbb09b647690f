// The tricycle's error term for one keyframe pair (shared/seeds/003, section 5):
// e = Z^-1 * h(X, Delta_r), h = T_bs^-1 * Delta_r * T_bs, whitened by the pair's covariance.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/tricycle_kinematics.h"

namespace odometry_calibration {

/// Cost functor for ceres::AutoDiffCostFunction<TricyclePairResidual, 3, 4, 3>: parameter blocks
/// are the kinematic 4-vector (TricycleParameterIndex) and the sensor pose (x, y, theta).
class TricyclePairResidual
{
public:
  /// Keeps a reference to `pair`, which must outlive the functor.
  TricyclePairResidual(const MotionPair& pair, const TricycleEncoderLayout& layout)
      : pair_(pair), layout_(layout)
  {
    // sqrt of the information matrix: L^-1 where covariance = L L^T, so |L^-1 e|^2 = e' S^-1 e.
    const Eigen::Matrix3d lower = pair.covariance.llt().matrixL();
    sqrt_information_ = lower.inverse();
  }

  template <typename T>
  bool operator()(const T* kinematic, const T* sensor_pose, T* residual) const
  {
    const Pose2T<T> T_base_sensor(sensor_pose[0], sensor_pose[1], sensor_pose[2]);
    const Pose2T<T> base_motion =
        integrateTricycleMotion(kinematic, layout_, pair_.encoder_samples);
    const Pose2T<T> predicted = sensorMotionFromBodyMotion(T_base_sensor, base_motion);
    const Eigen::Matrix<T, 3, 1> error =
        boxMinus(predicted, pair_.sensor_motion.template cast<T>());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

private:
  const MotionPair& pair_;
  TricycleEncoderLayout layout_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace odometry_calibration
