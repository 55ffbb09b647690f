// The differential drive's start values the model tests fit from: the nominal 0.077 m wheels
// and 0.33 m separation, the sensor guessed 0.1 m ahead of the axle.
#pragma once

#include "odometry_calibration/models/diff_drive_model.h"

namespace odometry_calibration {
namespace test {

inline DiffDriveOptions nominalDiffDriveOptions()
{
  DiffDriveOptions options;
  options.initial_left_radius_m = 0.077;
  options.initial_right_radius_m = 0.077;
  options.initial_separation_m = 0.33;
  options.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return options;
}

}  // namespace test
}  // namespace odometry_calibration
