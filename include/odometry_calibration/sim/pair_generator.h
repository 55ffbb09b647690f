// Keyframe pairs with a known truth, straight from the simulator (no laser, no scan matching):
// the encoder samples of each interval and the true sensor displacement plus Gaussian noise of
// a known sigma. For tests, benchmarks and model comparisons.
#pragma once

#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/sim/drive_plan.h"
#include "odometry_calibration/sim/imu_model.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"

namespace odometry_calibration {
namespace sim {

/// What to generate.
struct PairGeneratorOptions
{
  RobotOptions robot;                   ///< robot type and true parameters
  Pose2 T_base_sensor{0.15, 0.0, 0.0};  ///< true sensor pose
  DrivePlanOptions motion;              ///< drive (random by default) in an open 400 m field
  double duration_s = 120.0;            ///< simulated time [s]
  double encoder_rate_hz = 50.0;        ///< encoder samples per second
  double interval_s = 0.3;              ///< keyframe spacing [s]
  double translation_noise_m = 0.002;   ///< sigma of the added x, y noise [m]
  double rotation_noise_rad = 0.002;    ///< sigma of the added heading noise [rad]
  unsigned seed = 1;
  /// The true robot or laser changing during the run (Scenario::changes); the truth follows.
  /// Each pair's truth is taken at its encoder samples' instants, so a time_offset_change_s
  /// shows in no pair.
  std::vector<ParameterChange> changes;
  /// The IMU's gyro (off by default; its own random stream: the drive is the same either way).
  ImuOptions imu;
};

/// The pairs, the joints they carry (ticks), and the noise-free displacements.
struct GeneratedPairs
{
  std::vector<MotionPair> pairs;    ///< sensor_motion includes the noise
  std::vector<Pose2> true_motions;  ///< the same without noise
  JointLayout joints;               ///< names and kinds of EncoderSample::values
  std::vector<ImuSample> imu;       ///< the gyro's readings, with options.imu enabled
};

/// Runs the simulator and cuts the run into pairs. Throws std::invalid_argument for invalid
/// options.
GeneratedPairs generatePairs(const PairGeneratorOptions& options);

/// `options` with the scenario's robot, laser pose (as the sensor), motion, encoder rate,
/// duration, seed, changes and IMU; the keyframe interval and the noise stay `options`'.
PairGeneratorOptions pairGeneratorOptions(const Scenario& scenario, PairGeneratorOptions options);

}  // namespace sim
}  // namespace odometry_calibration
