#include "odometry_calibration/models/joint_fits.h"

#include <stdexcept>
#include <string>

#include "odometry_calibration/models/joint_parametric_fit.h"
#include "odometry_calibration/models/model_checks.h"

namespace odometry_calibration {
namespace {

/// One start pose and at least one pair set per sensor.
void requireSensors(const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                    const std::vector<Pose2>& start_poses, const std::string& model)
{
  if (pairs_per_sensor.empty())
    throw std::invalid_argument(model + " joint fit: no sensor's pairs given");
  if (start_poses.size() != pairs_per_sensor.size()) {
    throw std::invalid_argument(model + " joint fit: " + std::to_string(start_poses.size()) +
                                " start poses for " + std::to_string(pairs_per_sensor.size()) +
                                " sensors");
  }
}

}  // namespace

JointFitReport fitJointDiffDrive(const DiffDriveOptions& options,
                                 const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                 const std::vector<Pose2>& start_poses)
{
  validate(options);
  requireSensors(pairs_per_sensor, start_poses, "diff_drive");
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    const std::string which = "diff_drive joint fit, sensor " + std::to_string(s);
    requireEnoughPairs(pairs_per_sensor[s], 6, which);
    requirePairsWithJoints(pairs_per_sensor[s],
                           {options.layout.left_index, options.layout.right_index}, which,
                           "both wheel joints");
  }
  SensorMotionState<kDiffDriveParameterCount> start;
  start.intrinsics << options.initial_left_radius_m, options.initial_right_radius_m,
      options.initial_separation_m;
  return fitJointParametricModel<DiffDriveKinematics>(
      "diff_drive", pairs_per_sensor, options.layout,
      sensorMotionFitOptions(options.huber_threshold, options.max_iterations, options.yaw_starts),
      diffDriveParameters(), diffDriveMirrored, diffDriveObservabilityHints(), start, start_poses);
}

JointFitReport fitJointMecanum(const MecanumOptions& options,
                               const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                               const std::vector<Pose2>& start_poses)
{
  validate(options);
  requireSensors(pairs_per_sensor, start_poses, "mecanum");
  const MecanumEncoderLayout& layout = options.layout;
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    const std::string which = "mecanum joint fit, sensor " + std::to_string(s);
    requireEnoughPairs(pairs_per_sensor[s], 9, which);
    requirePairsWithJoints(pairs_per_sensor[s],
                           {layout.front_left_index, layout.front_right_index,
                            layout.rear_left_index, layout.rear_right_index},
                           which, "all four wheel joints");
  }
  SensorMotionState<kMecanumParameterCount> start;
  start.intrinsics << options.initial_radius_m[0], options.initial_radius_m[1],
      options.initial_radius_m[2], options.initial_radius_m[3], options.initial_lx_plus_ly_m;
  JointFitReport report = fitJointParametricModel<MecanumKinematics>(
      "mecanum", pairs_per_sensor, layout,
      sensorMotionFitOptions(options.huber_threshold, options.max_iterations, options.yaw_starts),
      mecanumParameters(), mecanumMirrored, mecanumObservabilityHints(), start, start_poses);
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    const std::vector<std::string> motion =
        mecanumMotionWarnings(mecanumMotionCoverage(pairs_per_sensor[s], layout, start.intrinsics));
    std::vector<std::string>& warnings = report.sensors[s].warnings;
    warnings.insert(warnings.begin(), motion.begin(), motion.end());
  }
  return report;
}

}  // namespace odometry_calibration
