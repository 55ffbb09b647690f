// Training samples for calibration: the interval between two keyframes, the decoded encoder
// samples inside it, and the sensor's measured displacement over it (paper Sec. III: the pairs
// (delta_jk, s_jk) with covariance Sigma_jk).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// One decoded encoder sample: cumulative counts of incremental joints, readings of absolute
/// joints, in the encoder's raw units (see EncoderDecoder).
struct EncoderSample
{
  double stamp_s = 0.0;    ///< time [s]
  Eigen::VectorXd values;  ///< one value per configured joint
};

/// One calibration sample over the keyframe interval [start_stamp_s, end_stamp_s].
struct MotionPair
{
  double start_stamp_s = 0.0;  ///< time of the first keyframe [s]
  double end_stamp_s = 0.0;    ///< time of the second keyframe [s]
  /// Encoder samples from the first keyframe to the second, both included (at least two).
  /// Models that integrate kinematics step through consecutive samples.
  std::vector<EncoderSample> encoder_samples;
  /// Measured sensor displacement s_hat: pose of the sensor at the end in the sensor frame at
  /// the start [m, m, rad].
  Pose2 sensor_motion;
  /// Covariance of sensor_motion (x, y, theta) [m^2, rad^2].
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

}  // namespace odometry_calibration
