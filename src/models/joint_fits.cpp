#include "odometry_calibration/models/joint_fits.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "odometry_calibration/models/joint_parametric_fit.h"
#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/tricycle_residual.h"

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

/// The joint differential-drive fit of `pairs_per_sensor`, reported as model `model`
/// (diff_drive, or skid_steer's virtual wheels).
JointFitReport fitJointDiffDriveAs(const std::string& model, const DiffDriveOptions& options,
                                   const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                   const std::vector<Pose2>& start_poses)
{
  validate(options);
  requireSensors(pairs_per_sensor, start_poses, model);
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    const std::string which = model + " joint fit, sensor " + std::to_string(s);
    requireEnoughPairs(pairs_per_sensor[s], 6, which);
    requirePairsWithJoints(pairs_per_sensor[s],
                           {options.layout.left_index, options.layout.right_index}, which,
                           "both wheel joints");
  }
  SensorMotionState<kDiffDriveParameterCount> start;
  start.intrinsics << options.initial_left_radius_m, options.initial_right_radius_m,
      options.initial_separation_m;
  return fitJointParametricModel<DiffDriveKinematics>(
      model, pairs_per_sensor, options.layout,
      sensorMotionFitOptions(options.huber_threshold, options.max_iterations, options.yaw_starts),
      diffDriveParameters(), diffDriveMirrored, diffDriveObservabilityHints(), start, start_poses);
}

/// Sensor `s`'s pairs checked for a tricycle fit alone: enough of them, each with two or more
/// encoder samples and the steering and traction joints.
void requireTricyclePairs(const std::vector<MotionPair>& pairs, const TricycleEncoderLayout& layout,
                          std::size_t s)
{
  const std::string which = "tricycle joint fit, sensor " + std::to_string(s);
  requireEnoughPairs(pairs, 7, which, "record a longer drive or shorten the keyframe interval");
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2)
      throw std::invalid_argument(which + ": every pair needs at least two encoder samples");
  }
  requirePairsWithJoints(pairs, {layout.steering_index, layout.traction_index}, which,
                         "the steering and traction joints");
}

}  // namespace

JointFitReport fitJointDiffDrive(const DiffDriveOptions& options,
                                 const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                 const std::vector<Pose2>& start_poses)
{
  return fitJointDiffDriveAs("diff_drive", options, pairs_per_sensor, start_poses);
}

JointFitReport fitJointSkidSteer(const SkidSteerOptions& options,
                                 const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                 const std::vector<Pose2>& start_poses)
{
  const DiffDriveOptions wheels = skidSteerVirtualWheels(options);  // validates the options
  std::vector<std::vector<MotionPair>> sides(pairs_per_sensor.size());
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    try {
      sides[s] = averageSidesOfPairs(pairs_per_sensor[s], options);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument("skid_steer joint fit, sensor " + std::to_string(s) + ": " +
                                  error.what());
    }
  }
  JointFitReport report = fitJointDiffDriveAs("skid_steer", wheels, sides, start_poses);
  report.derived = skidSteerMultipliers(report.intrinsics, options);
  for (ModelReport& alone : report.alone) {
    const std::vector<ParameterEstimate> multipliers =
        skidSteerMultipliers(alone.parameters, options);
    alone.parameters.insert(alone.parameters.end(), multipliers.begin(), multipliers.end());
  }
  return report;
}

JointFitReport fitJointTricycle(const TricycleModelOptions& options,
                                const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                const std::vector<Pose2>& start_poses)
{
  const auto started = std::chrono::steady_clock::now();
  const TricycleModel validated(options);  // throws for invalid options
  static_cast<void>(validated);
  requireSensors(pairs_per_sensor, start_poses, "tricycle");
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s)
    requireTricyclePairs(pairs_per_sensor[s], options.layout, s);
  JointFitReport report;
  report.model = "tricycle";
  JointStart<kTricycleParameterCount> joint{Eigen::Vector4d::Zero(), {}};
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    TricycleModelOptions own = options;
    own.initial.T_base_sensor = start_poses[s];
    TricycleModel alone(own);
    report.alone.push_back(alone.fit(pairs_per_sensor[s]));
    joint.intrinsic +=
        alone.parameters().kinematicVector() / static_cast<double>(pairs_per_sensor.size());
    joint.poses.push_back(alone.parameters().T_base_sensor.vector());
  }
  const TricycleCalibrationOptions& calibration = options.calibration;
  solveJointParametricModel<TricycleKinematics>(
      pairs_per_sensor, options.layout,
      sensorMotionFitOptions(calibration.huber_threshold, calibration.max_iterations,
                             calibration.yaw_starts),
      tricycleParameters(), tricycleObservabilityHints(), options.initial.kinematicVector(), joint,
      &report);
  report.fit_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return report;
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
