#include "odometry_calibration/models/tricycle_model.h"

#include <cmath>
#include <stdexcept>

#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"

namespace odometry_calibration {

TricycleModel::TricycleModel(TricycleModelOptions options)
    : options_(std::move(options)), parameters_(options_.initial)
{
  validate(options_.calibration);
  validateStartValues(options_.initial);
  if (!distinctJointIndices({options_.layout.steering_index, options_.layout.traction_index})) {
    throw std::invalid_argument("tricycle: steering and traction must be two different joints");
  }
  if (!(options_.layout.steering_ticks_per_turn > 0.0) ||
      !(options_.layout.traction_ticks_per_turn > 0.0)) {
    throw std::invalid_argument("tricycle: ticks per turn must be > 0");
  }
}

ModelReport TricycleModel::fit(const std::vector<MotionPair>& pairs)
{
  requirePairsWithJoints(pairs, {options_.layout.steering_index, options_.layout.traction_index},
                         "tricycle", "the steering and traction joints");
  const TricycleCalibrationResult result =
      calibrateTricycle(pairs, options_.layout, parameters_, options_.calibration);
  last_calibration_ = result;
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
  requirePredictionSamples(samples,
                           {options_.layout.steering_index, options_.layout.traction_index},
                           "tricycle", "joints");
  MotionPrediction prediction;
  prediction.mean = predictTricycleSensorMotion(parameters_, options_.layout, samples);
  prediction.covariance = residual_covariance_;
  return prediction;
}

namespace {

/// The numbers a tricycle model saves besides the sensor pose, each key once: the joints and
/// the kinematic parameters (the fitted ones when written, the start values when read back).
template <class Layout, class Parameters, class Visit>
void visitTricycleYaml(Layout& layout, Parameters& parameters, const Visit& visit)
{
  visit("steering_index", layout.steering_index);
  visit("traction_index", layout.traction_index);
  visit("steering_ticks_per_turn", layout.steering_ticks_per_turn);
  visit("traction_ticks_per_turn", layout.traction_ticks_per_turn);
  visit("steering_scale", parameters.steering_scale);
  visit("traction_scale_m_per_turn", parameters.traction_scale_m_per_turn);
  visit("axis_length_m", parameters.axis_length_m);
  visit("steering_offset_rad", parameters.steering_offset_rad);
}

}  // namespace

std::string TricycleModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    visitTricycleYaml(options_.layout, parameters_, YamlKeyWriter(out));
    // How a step's steering is read (tricycle_kinematics.h): a model fitted on the seed's logs
    // integrates with the end reading, and must do so again when loaded.
    out << YAML::Key << "steering_at_step_end" << YAML::Value
        << options_.layout.steering_at_step_end;
    emitSensorPoseYaml(out, parameters_.T_base_sensor, residual_covariance_);
  });
}

TricycleModel TricycleModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "tricycle", [](const YAML::Node& node) {
    TricycleModelOptions options;
    visitTricycleYaml(options.layout, options.initial, YamlKeyReader(node));
    // Absent (a model saved before the key existed): the layout's default, the mean of the
    // step's two readings.
    if (const YAML::Node at_end = node["steering_at_step_end"])
      options.layout.steering_at_step_end = at_end.as<bool>();
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    options.initial.T_base_sensor = sensor.T_base_sensor;
    TricycleModel model(options);
    model.residual_covariance_ = sensor.prediction_covariance;
    return model;
  });
}

}  // namespace odometry_calibration
