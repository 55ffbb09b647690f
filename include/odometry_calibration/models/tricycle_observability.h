// Says in words which tricycle parameters the data cannot determine, and why.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// Warnings about the motion in `pairs` (too little travel, no turns, turns one way only) and
/// about the fitted result (covariance unavailable, a parameter's sigma large against its value,
/// two parameters almost perfectly correlated). Each warning names the parameter(s) and the
/// motion that would fix it. Empty when everything is well determined.
std::vector<std::string> tricycleObservabilityWarnings(const std::vector<MotionPair>& pairs,
                                                       const TricycleCalibrationResult& result);

}  // namespace odometry_calibration
