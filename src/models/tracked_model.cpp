#include "odometry_calibration/models/tracked_model.h"

#include <cmath>

#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parametric_model.h"

namespace odometry_calibration {

const ParameterLayout& trackedParameters()
{
  static const ParameterLayout layout{
      {"left_wheel_radius", "right_wheel_radius", "wheel_separation", "separation_growth",
       "sensor_x", "sensor_y", "sensor_theta"},
      {"m", "m", "m", "m", "m", "m", "rad"},
      {"left_wheel_radius", "right_wheel_radius", "wheel_separation"}};
  return layout;
}

TrackedModel::TrackedModel(DiffDriveOptions options) : options_(std::move(options))
{
  validate(options_);
  state_.intrinsics << options_.initial_left_radius_m, options_.initial_right_radius_m,
      options_.initial_separation_m, 0.0;
  state_.T_base_sensor = options_.initial_T_base_sensor;
}

ModelReport TrackedModel::fit(const std::vector<MotionPair>& pairs)
{
  requireEnoughPairs(pairs, 8, "tracked calibration");
  requirePairsWithJoints(pairs, {options_.layout.left_index, options_.layout.right_index},
                         "tracked", "both wheel joints");
  // The mirrored solution (every intrinsic negated, the sensor turned by pi) has negative radii.
  ParametricFit fit = fitParametricModel<TrackedKinematics>(
      name(), pairs, options_.layout,
      sensorMotionFitOptions(options_.huber_threshold, options_.max_iterations,
                             options_.yaw_starts),
      trackedParameters(),
      [](const Eigen::Vector4d& intrinsics) {
        return intrinsics(kTrackedLeftRadius) + intrinsics(kTrackedRightRadius) < 0.0;
      },
      &state_);
  ObservabilityHints hints = diffDriveObservabilityHints();
  hints.unobservable_without_turning =
      "wheel_separation, separation_growth, the radii's difference and sensor_y";
  hints.relative_parameters = trackedParameters().relative;
  fit.report.warnings = observabilityWarnings(pairs, fit.report.parameters, state_.covariance,
                                              fit.covariance_available, hints, &fit.report.notes);
  return fit.report;
}

MotionPrediction TrackedModel::predict(const std::vector<EncoderSample>& samples) const
{
  requirePredictionSamples(samples, {options_.layout.left_index, options_.layout.right_index},
                           "tracked", "wheel joints");
  return predictSensorMotion<TrackedKinematics>(state_, options_.layout, samples);
}

double TrackedModel::separationAt(double nu) const
{
  return state_.intrinsics(kTrackedSeparation) + state_.intrinsics(kTrackedSeparationGrowth) * nu;
}

std::string TrackedModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    const Eigen::Vector4d& p = state_.intrinsics;
    const YamlKeyWriter visit(out);
    visitDiffDriveYaml(options_.layout, p(kTrackedLeftRadius), p(kTrackedRightRadius),
                       p(kTrackedSeparation), visit);
    visit("separation_growth_m", p(kTrackedSeparationGrowth));
    emitSensorPoseYaml(out, state_.T_base_sensor, state_.prediction_covariance);
  });
}

TrackedModel TrackedModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "tracked", [](const YAML::Node& node) {
    DiffDriveOptions options;
    double growth_m = 0.0;
    const YamlKeyReader visit(node);
    visitDiffDriveYaml(options.layout, options.initial_left_radius_m,
                       options.initial_right_radius_m, options.initial_separation_m, visit);
    visit("separation_growth_m", growth_m);
    const SensorPoseYaml sensor = readSensorPoseYaml(node);
    options.initial_T_base_sensor = sensor.T_base_sensor;
    TrackedModel model(options);
    model.state_.intrinsics(kTrackedSeparationGrowth) = growth_m;
    model.state_.prediction_covariance = sensor.prediction_covariance;
    return model;
  });
}

}  // namespace odometry_calibration
