// Ceres manifold for a pose stored as (x [m], y [m], theta [rad]): increments compose on the
// right, x ⊞ d = x ⊕ d, and y ⊟ x = ⊖x ⊕ y, so the angle never leaves (-pi, pi] and the
// optimiser steps in the pose's own frame (tricycle seed, section 3: box-plus on the state).
#pragma once

#include <ceres/autodiff_manifold.h>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// Plus/Minus functor for ceres::AutoDiffManifold<Se2PlusMinus, 3, 3>.
struct Se2PlusMinus
{
  template <typename T>
  bool Plus(const T* x, const T* delta, T* x_plus_delta) const
  {
    const Pose2T<T> result = Pose2T<T>(x[0], x[1], x[2]) * Pose2T<T>(delta[0], delta[1], delta[2]);
    x_plus_delta[0] = result.x();
    x_plus_delta[1] = result.y();
    x_plus_delta[2] = result.theta();
    return true;
  }

  template <typename T>
  bool Minus(const T* y, const T* x, T* y_minus_x) const
  {
    const Pose2T<T> result = between(Pose2T<T>(x[0], x[1], x[2]), Pose2T<T>(y[0], y[1], y[2]));
    y_minus_x[0] = result.x();
    y_minus_x[1] = result.y();
    y_minus_x[2] = result.theta();
    return true;
  }
};

/// A new SE(2) manifold; Ceres' Problem takes ownership when given to SetManifold.
inline ceres::Manifold* newSe2Manifold()
{
  return new ceres::AutoDiffManifold<Se2PlusMinus, 3, 3>();
}

}  // namespace odometry_calibration
