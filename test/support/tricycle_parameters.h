// The tricycle parameters the simulated tricycle tests share: a truth away from the real log's
// header (Ks 0.55, Kt 0.0108 m/turn, axis 1.6 m, steering offset -0.07 rad; sensor at
// (1.75 m, 0.03 m, 0.02 rad)) and the header's nominal values, which the fits start from.
#pragma once

#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {
namespace test {

inline TricycleParameters simulatedTricycleTruth()
{
  return TricycleParameters::fromVectors(Eigen::Vector4d(0.55, 0.0108, 1.6, -0.07),
                                         Eigen::Vector3d(1.75, 0.03, 0.02));
}

inline TricycleParameters tricycleLogNominal()
{
  return TricycleParameters::fromVectors(Eigen::Vector4d(0.1, 0.0106141, 1.4, 0.0),
                                         Eigen::Vector3d(1.5, 0.0, 0.0));
}

}  // namespace test
}  // namespace odometry_calibration
