#include "odometry_calibration/models/diff_drive_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/models/sensor_pose_yaml.h"

#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parameter_estimates.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/sensor_motion_fit.h"

namespace odometry_calibration {

void validate(const DiffDriveOptions& o)
{
  auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("diff_drive option '") + name + "' must be > 0");
    }
  };
  positive(o.layout.ticks_per_turn, "ticks_per_turn");
  // Start values may be negative (a mirrored start); the result is always the physical one.
  positive(std::abs(o.initial_left_radius_m), "initial_left_radius_m (absolute value)");
  positive(std::abs(o.initial_right_radius_m), "initial_right_radius_m (absolute value)");
  positive(std::abs(o.initial_separation_m), "initial_separation_m (absolute value)");
  if (o.layout.left_index < 0 || o.layout.right_index < 0 ||
      o.layout.left_index == o.layout.right_index) {
    throw std::invalid_argument("diff_drive options: left and right joints must be two joints");
  }
  if (o.max_iterations < 1) {
    throw std::invalid_argument("diff_drive option 'max_iterations' must be >= 1");
  }
  if (o.yaw_starts < 1 || o.yaw_starts > 360) {
    throw std::invalid_argument("diff_drive option 'yaw_starts' must be in [1, 360]");
  }
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
  throw std::invalid_argument(name.empty() ? "diff_drive needs two incremental joints"
                                           : "no joint named '" + name + "' in the pairs");
}

}  // namespace

DiffDriveEncoderLayout diffDriveLayoutForJoints(const JointLayout& joints,
                                                const std::string& left_joint,
                                                const std::string& right_joint,
                                                double ticks_per_turn)
{
  return {jointIndex(joints, left_joint, 0), jointIndex(joints, right_joint, 1), ticks_per_turn};
}

DiffDriveModel::DiffDriveModel(DiffDriveOptions options) : options_(std::move(options))
{
  validate(options_);
  intrinsics_ << options_.initial_left_radius_m, options_.initial_right_radius_m,
      options_.initial_separation_m;
  T_base_sensor_ = options_.initial_T_base_sensor;
}

namespace {

ResidualRms residualRms(const std::vector<MotionPair>& pairs, const DiffDriveEncoderLayout& layout,
                        const Eigen::Vector3d& intrinsics, const Pose2& T_base_sensor,
                        const std::vector<bool>* keep, Eigen::Vector3d* per_axis,
                        Eigen::Matrix3d* spread)
{
  return sensorMotionResidualRms<DiffDriveKinematics>(pairs, layout, intrinsics.data(),
                                                      T_base_sensor, keep, per_axis, spread);
}

}  // namespace

ModelReport DiffDriveModel::fit(const std::vector<MotionPair>& pairs)
{
  if (pairs.size() < 6) {
    throw std::invalid_argument("diff_drive calibration needs at least 6 keyframe pairs, got " +
                                std::to_string(pairs.size()) + ": record a longer drive");
  }
  const int needed = std::max(options_.layout.left_index, options_.layout.right_index) + 1;
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2 || pair.encoder_samples.front().values.size() < needed) {
      throw std::invalid_argument(
          "diff_drive: every pair needs two or more encoder samples with both wheel joints");
    }
  }
  ModelReport report;
  report.model = name();
  report.pairs_used = pairs.size();
  const Eigen::Vector3d start_intrinsics = intrinsics_;
  const Pose2 start_pose = T_base_sensor_;
  report.before =
      residualRms(pairs, options_.layout, intrinsics_, T_base_sensor_, nullptr, nullptr, nullptr);

  SensorMotionFitOptions fit_options;
  fit_options.huber_threshold = options_.huber_threshold;
  fit_options.max_iterations = options_.max_iterations;
  fit_options.yaw_starts = options_.yaw_starts;
  SensorMotionFit<3> fit = fitSensorMotion<DiffDriveKinematics>(pairs, options_.layout, intrinsics_,
                                                                T_base_sensor_, fit_options);
  // Sign ambiguity: (-r_L, -r_R, -b) with the sensor at (-x, -y, theta + pi) predicts the same
  // motions (the base motion is conjugated by a half turn). Keep the physical solution, with
  // positive radii; the covariance changes sign in the mixed blocks accordingly.
  if (fit.intrinsic(kLeftRadius) + fit.intrinsic(kRightRadius) < 0.0) {
    fit.intrinsic = -fit.intrinsic;
    fit.T_base_sensor = Pose2(-fit.T_base_sensor.x(), -fit.T_base_sensor.y(),
                              normalizeAngle(fit.T_base_sensor.theta() + M_PI));
    Eigen::Matrix<double, 6, 1> flip;
    flip << -1, -1, -1, -1, -1, 1;
    fit.covariance = flip.asDiagonal() * fit.covariance * flip.asDiagonal();
  }
  intrinsics_ = fit.intrinsic;
  T_base_sensor_ = fit.T_base_sensor;
  covariance_ = fit.covariance;

  report.after =
      residualRms(pairs, options_.layout, intrinsics_, T_base_sensor_, nullptr, nullptr, nullptr);
  residualRms(pairs, options_.layout, intrinsics_, T_base_sensor_, &fit.inlier,
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

  Eigen::Matrix<double, 6, 1> start, value;
  start << start_intrinsics, start_pose.vector();
  value << intrinsics_, T_base_sensor_.vector();
  const ParameterLayout& layout = diffDriveParameters();
  report.parameters = parameterEstimates(layout.names, layout.units, start, value, covariance_,
                                         fit.covariance_available);
  ObservabilityHints hints;
  hints.unobservable_without_turning = "wheel_separation, the radii's difference and sensor_y";
  hints.confused_by_one_way_turns =
      "the radii's difference is poorly separated from the sensor's position";
  hints.relative_parameters = layout.relative;
  report.warnings = observabilityWarnings(pairs, report.parameters, covariance_,
                                          fit.covariance_available, hints, &report.notes);
  return report;
}

MotionPrediction DiffDriveModel::predict(const std::vector<EncoderSample>& samples) const
{
  if (samples.size() < 2) {
    throw std::invalid_argument("diff_drive prediction needs at least two encoder samples");
  }
  requireJointIndices(samples, {options_.layout.left_index, options_.layout.right_index},
                      "diff_drive", "wheel joints");
  MotionPrediction prediction;
  prediction.mean = sensorMotionFromBodyMotion(
      T_base_sensor_, integrateDiffDriveMotion(intrinsics_.data(), options_.layout, samples));
  prediction.covariance = residual_covariance_;
  return prediction;
}

std::string DiffDriveModel::toYaml() const
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << name();
  out << YAML::Key << "left_index" << YAML::Value << options_.layout.left_index;
  out << YAML::Key << "right_index" << YAML::Value << options_.layout.right_index;
  out << YAML::Key << "ticks_per_turn" << YAML::Value << options_.layout.ticks_per_turn;
  out << YAML::Key << "left_wheel_radius_m" << YAML::Value << intrinsics_(kLeftRadius);
  out << YAML::Key << "right_wheel_radius_m" << YAML::Value << intrinsics_(kRightRadius);
  out << YAML::Key << "wheel_separation_m" << YAML::Value << intrinsics_(kWheelSeparation);
  emitSensorPoseYaml(out, T_base_sensor_, residual_covariance_);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

DiffDriveModel DiffDriveModel::fromYaml(const std::string& text)
{
  try {
    const YAML::Node node = YAML::Load(text);
    if (node["model"].as<std::string>() != "diff_drive") {
      throw std::runtime_error("not a diff_drive model");
    }
    DiffDriveOptions options;
    options.layout.left_index = node["left_index"].as<int>();
    options.layout.right_index = node["right_index"].as<int>();
    options.layout.ticks_per_turn = node["ticks_per_turn"].as<double>();
    options.initial_left_radius_m = node["left_wheel_radius_m"].as<double>();
    options.initial_right_radius_m = node["right_wheel_radius_m"].as<double>();
    options.initial_separation_m = node["wheel_separation_m"].as<double>();
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    options.initial_T_base_sensor = sensor.T_base_sensor;
    DiffDriveModel model(options);
    model.residual_covariance_ = sensor.prediction_covariance;
    return model;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("diff_drive model YAML: ") + error.what());
  }
}

}  // namespace odometry_calibration
