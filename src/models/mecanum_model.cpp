#include "odometry_calibration/models/mecanum_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/models/sensor_pose_yaml.h"

#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parameter_estimates.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/sensor_motion_fit.h"

namespace odometry_calibration {
namespace {

const char* const kWheelNames[4] = {"front_left", "front_right", "rear_left", "rear_right"};

std::array<int, 4> wheelIndices(const MecanumEncoderLayout& layout)
{
  return {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
          layout.rear_right_index};
}

std::string formatNumber(double value, int precision = 3)
{
  std::ostringstream stream;
  stream.precision(precision);
  stream << value;
  return stream.str();
}

}  // namespace

void validate(const MecanumOptions& o)
{
  auto positive = [](double value, const std::string& name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument("mecanum option '" + name + "' must be > 0");
    }
  };
  positive(o.layout.ticks_per_turn, "ticks_per_turn");
  // Start values may be negative (a mirrored start); the result is always the physical one.
  for (int i = 0; i < 4; ++i) {
    positive(std::abs(o.initial_radius_m[i]),
             std::string("initial radius of the ") + kWheelNames[i] + " wheel (absolute value)");
  }
  positive(std::abs(o.initial_lx_plus_ly_m), "initial_lx_plus_ly_m (absolute value)");
  std::array<int, 4> indices = wheelIndices(o.layout);
  if (*std::min_element(indices.begin(), indices.end()) < 0) {
    throw std::invalid_argument("mecanum options: a wheel joint index is negative");
  }
  std::sort(indices.begin(), indices.end());
  if (std::adjacent_find(indices.begin(), indices.end()) != indices.end()) {
    throw std::invalid_argument("mecanum options: the four wheels must be four different joints");
  }
  if (o.max_iterations < 1) {
    throw std::invalid_argument("mecanum option 'max_iterations' must be >= 1");
  }
  if (o.yaw_starts < 1 || o.yaw_starts > 360) {
    throw std::invalid_argument("mecanum option 'yaw_starts' must be in [1, 360]");
  }
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
      throw std::invalid_argument("no joint named '" + names[i] + "' in the pairs");
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
    intrinsics_(i) = options_.initial_radius_m[static_cast<std::size_t>(i)];
  intrinsics_(kLxPlusLy) = options_.initial_lx_plus_ly_m;
  T_base_sensor_ = options_.initial_T_base_sensor;
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

}  // namespace

ModelReport MecanumModel::fit(const std::vector<MotionPair>& pairs)
{
  if (pairs.size() < 9) {
    throw std::invalid_argument("mecanum calibration needs at least 9 keyframe pairs, got " +
                                std::to_string(pairs.size()) + ": record a longer drive");
  }
  const std::array<int, 4> index = wheelIndices(options_.layout);
  const int needed = *std::max_element(index.begin(), index.end()) + 1;
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2 || pair.encoder_samples.front().values.size() < needed) {
      throw std::invalid_argument(
          "mecanum: every pair needs two or more encoder samples with all four wheel joints");
    }
  }
  ModelReport report;
  report.model = name();
  report.pairs_used = pairs.size();
  const Eigen::Matrix<double, 5, 1> start_intrinsics = intrinsics_;
  const Pose2 start_pose = T_base_sensor_;
  report.before = sensorMotionResidualRms<MecanumKinematics>(pairs, options_.layout,
                                                             intrinsics_.data(), T_base_sensor_);

  SensorMotionFitOptions fit_options;
  fit_options.huber_threshold = options_.huber_threshold;
  fit_options.max_iterations = options_.max_iterations;
  fit_options.yaw_starts = options_.yaw_starts;
  SensorMotionFit<5> fit = fitSensorMotion<MecanumKinematics>(pairs, options_.layout, intrinsics_,
                                                              T_base_sensor_, fit_options);
  // Sign ambiguity: all radii and lx + ly negated with the sensor at (-x, -y, theta + pi)
  // predict the same motions (the base motion is conjugated by a half turn). Keep the physical
  // solution, with positive radii; the mixed blocks of the covariance change sign accordingly.
  if (fit.intrinsic.head<4>().sum() < 0.0) {
    fit.intrinsic = -fit.intrinsic;
    fit.T_base_sensor = Pose2(-fit.T_base_sensor.x(), -fit.T_base_sensor.y(),
                              normalizeAngle(fit.T_base_sensor.theta() + M_PI));
    Eigen::Matrix<double, 8, 1> flip;
    flip << -1, -1, -1, -1, -1, -1, -1, 1;
    fit.covariance = flip.asDiagonal() * fit.covariance * flip.asDiagonal();
  }
  intrinsics_ = fit.intrinsic;
  T_base_sensor_ = fit.T_base_sensor;
  covariance_ = fit.covariance;

  report.after = sensorMotionResidualRms<MecanumKinematics>(pairs, options_.layout,
                                                            intrinsics_.data(), T_base_sensor_);
  sensorMotionResidualRms<MecanumKinematics>(pairs, options_.layout, intrinsics_.data(),
                                             T_base_sensor_, &fit.inlier,
                                             &report.residual_rms_xytheta, &residual_covariance_);
  report.outliers = fit.outliers;
  report.rejected = fit.gross_outliers;
  report.down_weighted = fit.outliers - fit.gross_outliers;
  report.starts = fit.starts;
  report.starts_agreed = fit.starts_agreed;
  report.iterations = fit.iterations;
  report.converged = fit.converged;
  report.termination = fit.termination;
  report.fit_time_s = fit.solve_time_s;
  report.has_extrinsic = true;
  report.T_base_sensor = T_base_sensor_;

  const ParameterLayout& layout = mecanumParameters();
  Eigen::Matrix<double, 8, 1> start, value;
  start << start_intrinsics, start_pose.vector();
  value << intrinsics_, T_base_sensor_.vector();
  report.parameters = parameterEstimates(layout.names, layout.units, start, value, covariance_,
                                         fit.covariance_available);
  ObservabilityHints hints;
  hints.unobservable_without_turning = "lx_plus_ly, sensor_x and sensor_y";
  hints.confused_by_one_way_turns =
      "the radii's left-right difference is poorly separated from the sensor's position";
  hints.relative_parameters = layout.relative;
  const std::vector<std::string> general = observabilityWarnings(
      pairs, report.parameters, covariance_, fit.covariance_available, hints, &report.notes);
  // The mecanum coverage check names the missing motion (strafing, turning on the spot,
  // driving straight); it replaces the general "no turning" warning when it makes its own.
  report.warnings =
      mecanumMotionWarnings(mecanumMotionCoverage(pairs, options_.layout, start_intrinsics));
  const bool own_turning_warning =
      std::any_of(report.warnings.begin(), report.warnings.end(),
                  [](const std::string& warning) { return warning.rfind("no turning", 0) == 0; });
  for (const std::string& warning : general) {
    if (!(own_turning_warning && warning.rfind("no turning", 0) == 0))
      report.warnings.push_back(warning);
  }
  noteRadiiDisagreement(intrinsics_, covariance_, fit.covariance_available, &report.notes);
  return report;
}

MotionPrediction MecanumModel::predict(const std::vector<EncoderSample>& samples) const
{
  if (samples.size() < 2) {
    throw std::invalid_argument("mecanum prediction needs at least two encoder samples");
  }
  const std::array<int, 4> index = wheelIndices(options_.layout);
  requireJointIndices(samples, std::vector<int>(index.begin(), index.end()), "mecanum",
                      "wheel joints");
  MotionPrediction prediction;
  prediction.mean = sensorMotionFromBodyMotion(
      T_base_sensor_, integrateMecanumMotion(intrinsics_.data(), options_.layout, samples));
  prediction.covariance = residual_covariance_;
  return prediction;
}

std::string MecanumModel::toYaml() const
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << name();
  const std::array<int, 4> index = wheelIndices(options_.layout);
  out << YAML::Key << "wheel_indices" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i : index)
    out << i;
  out << YAML::EndSeq;
  out << YAML::Key << "ticks_per_turn" << YAML::Value << options_.layout.ticks_per_turn;
  out << YAML::Key << "wheel_radii_m" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < 4; ++i)
    out << intrinsics_(i);
  out << YAML::EndSeq;
  out << YAML::Key << "lx_plus_ly_m" << YAML::Value << intrinsics_(kLxPlusLy);
  emitSensorPoseYaml(out, T_base_sensor_, residual_covariance_);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

MecanumModel MecanumModel::fromYaml(const std::string& text)
{
  try {
    const YAML::Node node = YAML::Load(text);
    if (node["model"].as<std::string>() != "mecanum") {
      throw std::runtime_error("not a mecanum model");
    }
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
    model.residual_covariance_ = sensor.prediction_covariance;
    return model;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("mecanum model YAML: ") + error.what());
  }
}

}  // namespace odometry_calibration
