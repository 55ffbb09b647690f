#include "odometry_calibration/models/diff_drive_model.h"

#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/name_list.h"
#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parametric_model.h"

namespace odometry_calibration {

void validate(const DiffDriveOptions& o)
{
  requirePositiveOption(o.layout.ticks_per_turn, "diff_drive", "ticks_per_turn");
  // Start values may be negative (a mirrored start); the result is always the physical one.
  requirePositiveOption(std::abs(o.initial_left_radius_m), "diff_drive",
                        "initial_left_radius_m (absolute value)");
  requirePositiveOption(std::abs(o.initial_right_radius_m), "diff_drive",
                        "initial_right_radius_m (absolute value)");
  requirePositiveOption(std::abs(o.initial_separation_m), "diff_drive",
                        "initial_separation_m (absolute value)");
  if (!distinctJointIndices({o.layout.left_index, o.layout.right_index})) {
    throw std::invalid_argument("diff_drive options: left and right joints must be two joints");
  }
  requireSolverLimits(o.max_iterations, o.yaw_starts, "diff_drive");
}

namespace {

/// The joint named `name`, or for an empty name the `nth_incremental` incremental joint (from 0).
int jointIndex(const JointLayout& joints, const std::string& name, int nth_incremental)
{
  int seen = 0;
  for (std::size_t j = 0; j < joints.names.size(); ++j) {
    if (name.empty() ? (joints.kinds[j] == EncoderKind::kIncremental && seen++ == nth_incremental)
                     : joints.names[j] == name) {
      return static_cast<int>(j);
    }
  }
  throw std::invalid_argument(name.empty()
                                  ? "diff_drive needs two incremental joints"
                                  : "no joint named '" + name + "' in the pairs: they have " +
                                        quotedNames(joints.names));
}

}  // namespace

DiffDriveEncoderLayout diffDriveLayoutForJoints(const JointLayout& joints,
                                                const std::string& left_joint,
                                                const std::string& right_joint,
                                                double ticks_per_turn)
{
  return {jointIndex(joints, left_joint, 0), jointIndex(joints, right_joint, 1), ticks_per_turn};
}

ObservabilityHints diffDriveObservabilityHints()
{
  ObservabilityHints hints;
  hints.unobservable_without_turning = "wheel_separation, the radii's difference and sensor_y";
  hints.confused_by_one_way_turns =
      "the radii's difference is poorly separated from the sensor's position";
  hints.relative_parameters = diffDriveParameters().relative;
  return hints;
}

bool diffDriveMirrored(const Eigen::Vector3d& intrinsics)
{
  return intrinsics(kLeftRadius) + intrinsics(kRightRadius) < 0.0;
}

DiffDriveModel::DiffDriveModel(DiffDriveOptions options) : options_(std::move(options))
{
  validate(options_);
  state_.intrinsics << options_.initial_left_radius_m, options_.initial_right_radius_m,
      options_.initial_separation_m;
  state_.T_base_sensor = options_.initial_T_base_sensor;
}

ModelReport DiffDriveModel::fit(const std::vector<MotionPair>& pairs)
{
  requireEnoughPairs(pairs, 6, "diff_drive calibration");
  requirePairsWithJoints(pairs, {options_.layout.left_index, options_.layout.right_index},
                         "diff_drive", "both wheel joints");
  // Sign ambiguity: (-r_L, -r_R, -b) with the sensor at (-x, -y, theta + pi) predicts the same
  // motions. Keep the physical solution, with positive radii.
  ParametricFit fit = fitParametricModel<DiffDriveKinematics>(
      name(), pairs, options_.layout,
      sensorMotionFitOptions(options_.huber_threshold, options_.max_iterations,
                             options_.yaw_starts),
      diffDriveParameters(), diffDriveMirrored, &state_);
  fit.report.warnings = observabilityWarnings(pairs, fit.report.parameters, state_.covariance,
                                              fit.covariance_available,
                                              diffDriveObservabilityHints(), &fit.report.notes);
  return fit.report;
}

MotionPrediction DiffDriveModel::predict(const std::vector<EncoderSample>& samples) const
{
  requirePredictionSamples(samples, {options_.layout.left_index, options_.layout.right_index},
                           "diff_drive", "wheel joints");
  return predictSensorMotion<DiffDriveKinematics>(state_, options_.layout, samples);
}

std::string DiffDriveModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    const Eigen::Vector3d& intrinsics = state_.intrinsics;
    visitDiffDriveYaml(options_.layout, intrinsics(kLeftRadius), intrinsics(kRightRadius),
                       intrinsics(kWheelSeparation), YamlKeyWriter(out));
    emitSensorPoseYaml(out, state_.T_base_sensor, state_.prediction_covariance);
  });
}

DiffDriveModel DiffDriveModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "diff_drive", [](const YAML::Node& node) {
    DiffDriveOptions options;
    visitDiffDriveYaml(options.layout, options.initial_left_radius_m,
                       options.initial_right_radius_m, options.initial_separation_m,
                       YamlKeyReader(node));
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    options.initial_T_base_sensor = sensor.T_base_sensor;
    DiffDriveModel model(options);
    model.state_.prediction_covariance = sensor.prediction_covariance;
    return model;
  });
}

}  // namespace odometry_calibration
