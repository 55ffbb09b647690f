#include "odometry_calibration/models/base_odometry_model.h"

#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/name_list.h"
#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/parametric_model.h"

namespace odometry_calibration {

const std::vector<std::string>& baseOdometryJointNames()
{
  static const std::vector<std::string> names = {"base_forward", "base_lateral", "base_yaw"};
  return names;
}

void validate(const BaseOdometryOptions& o)
{
  requirePositiveOption(o.initial_translation_scale, "base_odometry", "translation_scale");
  requirePositiveOption(o.initial_rotation_scale, "base_odometry", "rotation_scale");
  if (!distinctJointIndices({o.layout.forward_index, o.layout.lateral_index, o.layout.yaw_index}))
    throw std::invalid_argument("base_odometry options: the three joints must be distinct");
  requireSolverLimits(o.max_iterations, o.yaw_starts, "base_odometry");
}

BaseOdometryLayout baseOdometryLayoutForJoints(const JointLayout& joints)
{
  int index[3] = {-1, -1, -1};
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t j = 0; j < joints.names.size(); ++j) {
      if (joints.names[j] == baseOdometryJointNames()[k])
        index[k] = static_cast<int>(j);
    }
    if (index[k] < 0) {
      throw std::invalid_argument("base_odometry: no joint named '" + baseOdometryJointNames()[k] +
                                  "' in the pairs (they have " + quotedNames(joints.names) +
                                  "): the model needs wheels.source odometry");
    }
  }
  return {index[0], index[1], index[2]};
}

namespace {

ObservabilityHints baseOdometryObservabilityHints()
{
  ObservabilityHints hints;
  hints.unobservable_without_turning = "rotation_scale, sensor_x and sensor_y";
  hints.confused_by_one_way_turns =
      "the rotation scale is poorly separated from the sensor's position";
  hints.relative_parameters = baseOdometryParameters().relative;
  return hints;
}

std::vector<int> joints(const BaseOdometryLayout& layout)
{
  return {layout.forward_index, layout.lateral_index, layout.yaw_index};
}

}  // namespace

BaseOdometryModel::BaseOdometryModel(BaseOdometryOptions options) : options_(std::move(options))
{
  validate(options_);
  state_.intrinsics << options_.initial_translation_scale, options_.initial_rotation_scale;
  state_.T_base_sensor = options_.initial_T_base_sensor;
}

ModelReport BaseOdometryModel::fit(const std::vector<MotionPair>& pairs)
{
  requireEnoughPairs(pairs, 5, "base_odometry calibration");
  requirePairsWithJoints(pairs, joints(options_.layout), "base_odometry",
                         "the base odometry's joints");
  // The one mirrored solution, (-k_t, k_r) with the sensor at (-x, -y, theta + pi) (a half turn
  // conjugates the base motion: its translation flips, its rotation stays), is not the one of
  // mirrorSensorMotionFit (which flips every intrinsic): a fit that lands there is turned over
  // and polished from the physical side with one start.
  const auto never = [](const Eigen::Vector2d&) { return false; };
  SensorMotionFitOptions solver = sensorMotionFitOptions(
      options_.huber_threshold, options_.max_iterations, options_.yaw_starts);
  const SensorMotionState<kBaseOdometryParameterCount> start = state_;
  ParametricFit fit = fitParametricModel<BaseOdometryKinematics>(
      name(), pairs, options_.layout, solver, baseOdometryParameters(), never, &state_);
  if (state_.intrinsics(kTranslationScale) < 0.0) {
    const Pose2 mirrored(-state_.T_base_sensor.x(), -state_.T_base_sensor.y(),
                         normalizeAngle(state_.T_base_sensor.theta() + M_PI));
    const ResidualRms before = fit.report.before;
    state_.intrinsics(kTranslationScale) = -state_.intrinsics(kTranslationScale);
    state_.T_base_sensor = mirrored;
    solver.yaw_starts = 1;
    fit = fitParametricModel<BaseOdometryKinematics>(name(), pairs, options_.layout, solver,
                                                     baseOdometryParameters(), never, &state_);
    fit.report.before = before;
    for (std::size_t k = 0; k < fit.report.parameters.size(); ++k)
      fit.report.parameters[k].initial =
          k < 2 ? start.intrinsics(static_cast<Eigen::Index>(k))
                : start.T_base_sensor.vector()(static_cast<Eigen::Index>(k - 2));
  }
  fit.report.warnings = observabilityWarnings(pairs, fit.report.parameters, state_.covariance,
                                              fit.covariance_available,
                                              baseOdometryObservabilityHints(), &fit.report.notes);
  return fit.report;
}

MotionPrediction BaseOdometryModel::predict(const std::vector<EncoderSample>& samples) const
{
  requirePredictionSamples(samples, joints(options_.layout), "base_odometry",
                           "base odometry joints");
  return predictSensorMotion<BaseOdometryKinematics>(state_, options_.layout, samples);
}

namespace {

/// The numbers a base_odometry model saves besides the sensor pose, each key once.
template <class Layout, class Number, class Visit>
void visitBaseOdometryYaml(Layout& layout, Number& translation_scale, Number& rotation_scale,
                           const Visit& visit)
{
  visit("forward_index", layout.forward_index);
  visit("lateral_index", layout.lateral_index);
  visit("yaw_index", layout.yaw_index);
  visit("translation_scale", translation_scale);
  visit("rotation_scale", rotation_scale);
}

}  // namespace

std::string BaseOdometryModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    const Eigen::Vector2d& scales = state_.intrinsics;
    visitBaseOdometryYaml(options_.layout, scales(kTranslationScale), scales(kRotationScale),
                          YamlKeyWriter(out));
    emitSensorPoseYaml(out, state_.T_base_sensor, state_.prediction_covariance);
  });
}

BaseOdometryModel BaseOdometryModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "base_odometry", [](const YAML::Node& node) {
    BaseOdometryOptions options;
    visitBaseOdometryYaml(options.layout, options.initial_translation_scale,
                          options.initial_rotation_scale, YamlKeyReader(node));
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    options.initial_T_base_sensor = sensor.T_base_sensor;
    BaseOdometryModel model(options);
    model.state_.prediction_covariance = sensor.prediction_covariance;
    return model;
  });
}

}  // namespace odometry_calibration
