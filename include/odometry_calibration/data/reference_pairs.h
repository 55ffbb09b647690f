// Keyframe pairs from an ego-motion reference sampled with the encoders (a tracker, another
// odometry): one sensor pose per encoder sample, the measured displacement of a window being
// the reference's relative pose between its first and last sample.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// One pair per window of at least `interval_s` [s], the windows end to end (keyframes of
/// selectKeyframeWindows). Each pair gets `covariance` [m^2, rad^2]. Throws std::invalid_argument
/// unless there is one pose per sample, the interval is > 0 and times do not decrease.
std::vector<MotionPair> referencePairs(const std::vector<EncoderSample>& samples,
                                       const std::vector<Pose2>& T_world_sensor, double interval_s,
                                       const Eigen::Matrix3d& covariance);

}  // namespace odometry_calibration
