#include "odometry_calibration/models/mecanum_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/name_list.h"
#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parametric_model.h"

namespace odometry_calibration {
namespace {

const char* const kWheelNames[4] = {"front_left", "front_right", "rear_left", "rear_right"};

std::array<int, 4> wheelIndices(const MecanumEncoderLayout& layout)
{
  return {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
          layout.rear_right_index};
}

}  // namespace

void validate(const MecanumOptions& o)
{
  requirePositiveOption(o.layout.ticks_per_turn, "mecanum", "ticks_per_turn");
  // Start values may be negative (a mirrored start); the result is always the physical one.
  for (int i = 0; i < 4; ++i) {
    requirePositiveOption(
        std::abs(o.initial_radius_m[i]), "mecanum",
        std::string("initial radius of the ") + kWheelNames[i] + " wheel (absolute value)");
  }
  requirePositiveOption(std::abs(o.initial_lx_plus_ly_m), "mecanum",
                        "initial_lx_plus_ly_m (absolute value)");
  const std::array<int, 4> indices = wheelIndices(o.layout);
  if (*std::min_element(indices.begin(), indices.end()) < 0) {
    throw std::invalid_argument("mecanum options: a wheel joint index is negative");
  }
  if (!distinctJointIndices(std::vector<int>(indices.begin(), indices.end()))) {
    throw std::invalid_argument("mecanum options: the four wheels must be four different joints");
  }
  requireSolverLimits(o.max_iterations, o.yaw_starts, "mecanum");
}

MecanumEncoderLayout mecanumLayoutForJoints(const JointLayout& joints,
                                            const std::array<std::string, 4>& names,
                                            double ticks_per_turn)
{
  std::vector<int> incremental;
  for (std::size_t j = 0; j < joints.names.size(); ++j) {
    if (joints.kinds[j] == EncoderKind::kIncremental)
      incremental.push_back(static_cast<int>(j));
  }
  std::array<int, 4> index{};
  for (int i = 0; i < 4; ++i) {
    if (names[i].empty()) {
      if (static_cast<int>(incremental.size()) <= i) {
        throw std::invalid_argument(
            "mecanum needs four incremental joints (front left, front "
            "right, rear left, rear right), the pairs have " +
            std::to_string(incremental.size()));
      }
      index[i] = incremental[static_cast<std::size_t>(i)];
      continue;
    }
    const auto found = std::find(joints.names.begin(), joints.names.end(), names[i]);
    if (found == joints.names.end()) {
      throw std::invalid_argument("no joint named '" + names[i] + "' in the pairs: they have " +
                                  quotedNames(joints.names));
    }
    index[i] = static_cast<int>(found - joints.names.begin());
  }
  MecanumEncoderLayout layout;
  layout.front_left_index = index[0];
  layout.front_right_index = index[1];
  layout.rear_left_index = index[2];
  layout.rear_right_index = index[3];
  layout.ticks_per_turn = ticks_per_turn;
  return layout;
}

MecanumModel::MecanumModel(MecanumOptions options) : options_(std::move(options))
{
  validate(options_);
  for (int i = 0; i < 4; ++i)
    state_.intrinsics(i) = options_.initial_radius_m[static_cast<std::size_t>(i)];
  state_.intrinsics(kLxPlusLy) = options_.initial_lx_plus_ly_m;
  state_.T_base_sensor = options_.initial_T_base_sensor;
}

namespace {

/// A note when the fitted radii differ from their mean beyond 3 sigma (and 0.1 %): a real
/// difference, or a deformation the model does not describe (an unaligned or tilted wheel leaks
/// into the radii and the sensor yaw).
void noteRadiiDisagreement(const Eigen::Matrix<double, 5, 1>& intrinsics,
                           const Eigen::Matrix<double, 8, 8>& covariance, bool available,
                           std::vector<std::string>* notes)
{
  if (!available)
    return;
  const double mean = intrinsics.head<4>().mean();
  std::string beyond;
  for (int i = 0; i < 4; ++i) {
    Eigen::Matrix<double, 4, 1> gradient = Eigen::Matrix<double, 4, 1>::Constant(-0.25);
    gradient(i) += 1.0;
    const double sigma =
        std::sqrt(std::max(0.0, gradient.dot(covariance.topLeftCorner<4, 4>() * gradient)));
    const double difference = intrinsics(i) - mean;
    if (std::abs(difference) > 3.0 * sigma && std::abs(difference) > 1e-3 * std::abs(mean)) {
      beyond += std::string(beyond.empty() ? "" : ", ") + kWheelNames[i] + " " +
                formatNumber(100.0 * difference / mean, 2) + " % (sigma " +
                formatNumber(100.0 * sigma / std::abs(mean), 2) + " %)";
    }
  }
  if (!beyond.empty()) {
    notes->push_back(
        "the wheel radii differ from their mean beyond 3 sigma (" + beyond +
        "): either the wheels really differ, or the robot deviates from the mecanum model (an "
        "unaligned or tilted wheel shows up as different radii and a shifted sensor_theta); if "
        "the model-free gp predicts clearly better, trust it rather than these radii");
  }
}

/// The warnings of a mecanum fit: the coverage check's, which name the missing motion
/// (strafing, turning on the spot, driving straight), then the general ones (`general`), less
/// the general "no turning" warning when the coverage check made its own.
std::vector<std::string> mecanumWarnings(const std::vector<std::string>& coverage,
                                         const std::vector<std::string>& general)
{
  std::vector<std::string> warnings = coverage;
  const bool own_turning_warning =
      std::any_of(warnings.begin(), warnings.end(),
                  [](const std::string& warning) { return warning.rfind("no turning", 0) == 0; });
  for (const std::string& warning : general) {
    if (!(own_turning_warning && warning.rfind("no turning", 0) == 0))
      warnings.push_back(warning);
  }
  return warnings;
}

}  // namespace

ObservabilityHints mecanumObservabilityHints()
{
  ObservabilityHints hints;
  hints.unobservable_without_turning = "lx_plus_ly, sensor_x and sensor_y";
  hints.confused_by_one_way_turns =
      "the radii's left-right difference is poorly separated from the sensor's position";
  hints.relative_parameters = mecanumParameters().relative;
  return hints;
}

bool mecanumMirrored(const Eigen::Matrix<double, 5, 1>& intrinsics)
{
  return intrinsics.head<4>().sum() < 0.0;
}

ModelReport MecanumModel::fit(const std::vector<MotionPair>& pairs)
{
  requireEnoughPairs(pairs, 9, "mecanum calibration");
  const std::array<int, 4> index = wheelIndices(options_.layout);
  requirePairsWithJoints(pairs, std::vector<int>(index.begin(), index.end()), "mecanum",
                         "all four wheel joints");
  const Eigen::Matrix<double, 5, 1> start_intrinsics = state_.intrinsics;
  // Sign ambiguity (mecanumMirrored): keep the physical solution, with positive radii.
  ParametricFit fit = fitParametricModel<MecanumKinematics>(
      name(), pairs, options_.layout,
      sensorMotionFitOptions(options_.huber_threshold, options_.max_iterations,
                             options_.yaw_starts),
      mecanumParameters(), mecanumMirrored, &state_);
  ModelReport& report = fit.report;
  const std::vector<std::string> general =
      observabilityWarnings(pairs, report.parameters, state_.covariance, fit.covariance_available,
                            mecanumObservabilityHints(), &report.notes);
  report.warnings = mecanumWarnings(
      mecanumMotionWarnings(mecanumMotionCoverage(pairs, options_.layout, start_intrinsics)),
      general);
  noteRadiiDisagreement(state_.intrinsics, state_.covariance, fit.covariance_available,
                        &report.notes);
  return report;
}

MotionPrediction MecanumModel::predict(const std::vector<EncoderSample>& samples) const
{
  const std::array<int, 4> index = wheelIndices(options_.layout);
  requirePredictionSamples(samples, std::vector<int>(index.begin(), index.end()), "mecanum",
                           "wheel joints");
  return predictSensorMotion<MecanumKinematics>(state_, options_.layout, samples);
}

std::string MecanumModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    const std::array<int, 4> index = wheelIndices(options_.layout);
    out << YAML::Key << "wheel_indices" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (int i : index)
      out << i;
    out << YAML::EndSeq;
    out << YAML::Key << "ticks_per_turn" << YAML::Value << options_.layout.ticks_per_turn;
    out << YAML::Key << "wheel_radii_m" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (int i = 0; i < 4; ++i)
      out << state_.intrinsics(i);
    out << YAML::EndSeq;
    out << YAML::Key << "lx_plus_ly_m" << YAML::Value << state_.intrinsics(kLxPlusLy);
    emitSensorPoseYaml(out, state_.T_base_sensor, state_.prediction_covariance);
  });
}

MecanumModel MecanumModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "mecanum", [](const YAML::Node& node) {
    const auto index = node["wheel_indices"].as<std::vector<int>>();
    const auto radii = node["wheel_radii_m"].as<std::vector<double>>();
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    if (index.size() != 4 || radii.size() != 4)
      throw std::runtime_error("wheel_indices and wheel_radii_m need 4 values");
    MecanumOptions options;
    options.layout.front_left_index = index[0];
    options.layout.front_right_index = index[1];
    options.layout.rear_left_index = index[2];
    options.layout.rear_right_index = index[3];
    options.layout.ticks_per_turn = node["ticks_per_turn"].as<double>();
    std::copy(radii.begin(), radii.end(), options.initial_radius_m.begin());
    options.initial_lx_plus_ly_m = node["lx_plus_ly_m"].as<double>();
    options.initial_T_base_sensor = sensor.T_base_sensor;
    MecanumModel model(options);
    model.state_.prediction_covariance = sensor.prediction_covariance;
    return model;
  });
}

}  // namespace odometry_calibration
