#include "odometry_calibration/models/tricycle_model.h"

#include <algorithm>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/models/sensor_pose_yaml.h"

namespace odometry_calibration {

TricycleModel::TricycleModel(TricycleModelOptions options)
    : options_(std::move(options)), parameters_(options_.initial)
{
  validate(options_.calibration);
  validateStartValues(options_.initial);
  if (options_.layout.steering_index < 0 || options_.layout.traction_index < 0 ||
      options_.layout.steering_index == options_.layout.traction_index) {
    throw std::invalid_argument("tricycle: steering and traction must be two different joints");
  }
  if (!(options_.layout.steering_ticks_per_turn > 0.0) ||
      !(options_.layout.traction_ticks_per_turn > 0.0)) {
    throw std::invalid_argument("tricycle: ticks per turn must be > 0");
  }
}

ModelReport TricycleModel::fit(const std::vector<MotionPair>& pairs)
{
  const int needed = std::max(options_.layout.steering_index, options_.layout.traction_index) + 1;
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2 || pair.encoder_samples.front().values.size() < needed) {
      throw std::invalid_argument(
          "tricycle: every pair needs two or more encoder samples with the steering and "
          "traction joints");
    }
  }
  const TricycleCalibrationResult result =
      calibrateTricycle(pairs, options_.layout, parameters_, options_.calibration);
  ModelReport report;
  report.model = name();
  report.parameters = result.estimates;
  report.before = result.before;
  report.after = result.after;
  report.pairs_used = result.pair_count;
  report.outliers = result.outlier_count;
  report.rejected = result.gross_outliers;
  report.down_weighted = result.outlier_count - result.gross_outliers;
  report.starts = result.starts;
  report.starts_agreed = result.starts_agreed;
  report.notes = result.notes;
  report.iterations = result.iterations;
  report.converged = result.converged;
  report.termination = result.termination;
  report.fit_time_s = result.solve_time_s;
  report.warnings = result.warnings;
  if (!result.converged)
    return report;  // the parameters stay as they were
  parameters_ = result.calibrated;
  report.has_extrinsic = true;
  report.T_base_sensor = parameters_.T_base_sensor;
  // Per-axis spread of the inlier residuals: the prediction's covariance over one pair.
  const double t = result.after_inliers.translation_m, r = result.after_inliers.rotation_rad;
  report.residual_rms_xytheta = Eigen::Vector3d(t / std::sqrt(2.0), t / std::sqrt(2.0), r);
  residual_covariance_ = report.residual_rms_xytheta.cwiseAbs2().asDiagonal();
  return report;
}

MotionPrediction TricycleModel::predict(const std::vector<EncoderSample>& samples) const
{
  if (samples.size() < 2)
    throw std::invalid_argument("tricycle prediction needs at least two encoder samples");
  requireJointIndices(samples, {options_.layout.steering_index, options_.layout.traction_index},
                      "tricycle", "joints");
  MotionPrediction prediction;
  prediction.mean = predictTricycleSensorMotion(parameters_, options_.layout, samples);
  prediction.covariance = residual_covariance_;
  return prediction;
}

std::string TricycleModel::toYaml() const
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  const TricycleParameters& p = parameters_;
  const TricycleEncoderLayout& l = options_.layout;
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << name();
  out << YAML::Key << "steering_index" << YAML::Value << l.steering_index;
  out << YAML::Key << "traction_index" << YAML::Value << l.traction_index;
  out << YAML::Key << "steering_ticks_per_turn" << YAML::Value << l.steering_ticks_per_turn;
  out << YAML::Key << "traction_ticks_per_turn" << YAML::Value << l.traction_ticks_per_turn;
  out << YAML::Key << "steering_scale" << YAML::Value << p.steering_scale;
  out << YAML::Key << "traction_scale_m_per_turn" << YAML::Value << p.traction_scale_m_per_turn;
  out << YAML::Key << "axis_length_m" << YAML::Value << p.axis_length_m;
  out << YAML::Key << "steering_offset_rad" << YAML::Value << p.steering_offset_rad;
  emitSensorPoseYaml(out, p.T_base_sensor, residual_covariance_);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

TricycleModel TricycleModel::fromYaml(const std::string& text)
{
  try {
    const YAML::Node node = YAML::Load(text);
    if (node["model"].as<std::string>() != "tricycle")
      throw std::runtime_error("not a tricycle model");
    TricycleModelOptions options;
    options.layout.steering_index = node["steering_index"].as<int>();
    options.layout.traction_index = node["traction_index"].as<int>();
    options.layout.steering_ticks_per_turn = node["steering_ticks_per_turn"].as<double>();
    options.layout.traction_ticks_per_turn = node["traction_ticks_per_turn"].as<double>();
    TricycleParameters& p = options.initial;
    p.steering_scale = node["steering_scale"].as<double>();
    p.traction_scale_m_per_turn = node["traction_scale_m_per_turn"].as<double>();
    p.axis_length_m = node["axis_length_m"].as<double>();
    p.steering_offset_rad = node["steering_offset_rad"].as<double>();
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    p.T_base_sensor = sensor.T_base_sensor;
    TricycleModel model(options);
    model.residual_covariance_ = sensor.prediction_covariance;
    return model;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("tricycle model YAML: ") + error.what());
  }
}

}  // namespace odometry_calibration
