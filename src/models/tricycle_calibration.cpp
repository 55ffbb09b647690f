#include "odometry_calibration/models/tricycle_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parameter_estimates.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/parametric_model.h"
#include "odometry_calibration/models/tricycle_residual.h"

namespace odometry_calibration {

Eigen::Vector4d TricycleParameters::kinematicVector() const
{
  Eigen::Vector4d v;
  v(kSteeringScale) = steering_scale;
  v(kTractionScale) = traction_scale_m_per_turn;
  v(kAxisLength) = axis_length_m;
  v(kSteeringOffset) = steering_offset_rad;
  return v;
}

TricycleParameters TricycleParameters::fromVectors(const Eigen::Vector4d& kinematic,
                                                   const Eigen::Vector3d& sensor_pose)
{
  TricycleParameters p;
  p.steering_scale = kinematic(kSteeringScale);
  p.traction_scale_m_per_turn = kinematic(kTractionScale);
  p.axis_length_m = kinematic(kAxisLength);
  p.steering_offset_rad = kinematic(kSteeringOffset);
  p.T_base_sensor = Pose2(sensor_pose(0), sensor_pose(1), normalizeAngle(sensor_pose(2)));
  return p;
}

void validate(const TricycleCalibrationOptions& options)
{
  if (!(options.translation_sigma_m > 0.0) || !std::isfinite(options.translation_sigma_m)) {
    throw std::invalid_argument("translation_sigma_m must be a positive number of metres");
  }
  if (!(options.rotation_sigma_rad > 0.0) || !std::isfinite(options.rotation_sigma_rad)) {
    throw std::invalid_argument("rotation_sigma_rad must be a positive number of radians");
  }
  if (!std::isfinite(options.huber_threshold)) {
    throw std::invalid_argument("huber_threshold must be a number (<= 0 disables the robust loss)");
  }
  if (options.max_iterations < 1) {
    throw std::invalid_argument("max_iterations must be at least 1");
  }
  if (options.yaw_starts < 1 || options.yaw_starts > 360) {
    throw std::invalid_argument("yaw_starts must be in [1, 360]");
  }
}

Pose2 predictTricycleSensorMotion(const TricycleParameters& parameters,
                                  const TricycleEncoderLayout& layout,
                                  const std::vector<EncoderSample>& samples)
{
  const Eigen::Vector4d kinematic = parameters.kinematicVector();
  const Pose2 base_motion = integrateTricycleMotion(kinematic.data(), layout, samples);
  return sensorMotionFromBodyMotion(parameters.T_base_sensor, base_motion);
}

std::vector<Pose2> tricycleSensorTrajectory(const TricycleParameters& parameters,
                                            const TricycleEncoderLayout& layout,
                                            const std::vector<EncoderSample>& samples,
                                            const Pose2& T_world_sensor_start)
{
  std::vector<Pose2> trajectory;
  if (samples.empty()) {
    return trajectory;
  }
  trajectory.reserve(samples.size());
  trajectory.push_back(T_world_sensor_start);
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const std::vector<EncoderSample> step = {samples[k - 1], samples[k]};
    trajectory.push_back(trajectory.back() * predictTricycleSensorMotion(parameters, layout, step));
  }
  return trajectory;
}

ResidualRms tricycleResidualRms(const std::vector<MotionPair>& pairs,
                                const TricycleEncoderLayout& layout,
                                const TricycleParameters& parameters)
{
  ResidualRms rms;
  double sum_translation = 0.0;
  double sum_rotation = 0.0;
  for (const MotionPair& pair : pairs) {
    const Eigen::Vector3d error = boxMinus(
        predictTricycleSensorMotion(parameters, layout, pair.encoder_samples), pair.sensor_motion);
    sum_translation += error.head<2>().squaredNorm();
    sum_rotation += error(2) * error(2);
  }
  rms.count = pairs.size();
  if (!pairs.empty()) {
    rms.translation_m = std::sqrt(sum_translation / pairs.size());
    rms.rotation_rad = std::sqrt(sum_rotation / pairs.size());
  }
  return rms;
}

namespace {

std::vector<ParameterEstimate> makeEstimates(const TricycleParameters& initial,
                                             const TricycleParameters& calibrated,
                                             const Eigen::Matrix<double, 7, 7>& covariance,
                                             bool covariance_available)
{
  Eigen::Matrix<double, 7, 1> start;
  start << initial.kinematicVector(), initial.T_base_sensor.vector();
  Eigen::Matrix<double, 7, 1> value;
  value << calibrated.kinematicVector(), calibrated.T_base_sensor.vector();
  return parameterEstimates(tricycleParameters().names, tricycleParameters().units, start, value,
                            covariance, covariance_available);
}

}  // namespace

void validateStartValues(const TricycleParameters& p)
{
  const Eigen::Vector4d k = p.kinematicVector();
  if (!k.allFinite() || !p.T_base_sensor.vector().allFinite()) {
    throw std::invalid_argument("tricycle start values must be finite numbers");
  }
  // A zero scale or axis length makes the model degenerate (no motion, or a division by zero);
  // a negative one describes a mirrored robot. Both are configuration errors.
  if (!(p.steering_scale > 0.0) || !(p.traction_scale_m_per_turn > 0.0) ||
      !(p.axis_length_m > 0.0)) {
    throw std::invalid_argument(
        "tricycle start values: Ksteer, Ktraction and axis_length must be > 0 (got " +
        std::to_string(p.steering_scale) + ", " + std::to_string(p.traction_scale_m_per_turn) +
        ", " + std::to_string(p.axis_length_m) + ")");
  }
}

namespace {

/// Keeps the physical one of the tricycle's symmetric solutions (which the global starts can
/// land in): (Ks, -Kt, -a, ds) with the sensor at (-x, -y, theta + pi) predicts the same
/// motions (the base motion is conjugated by a half turn), and so does (Ks, -Kt, a, ds + pi)
/// (the wheel pointing the other way, rolling backwards). The physical solution has a positive
/// axis length and traction scale; the covariance changes sign accordingly.
void keepPhysicalTricycleSolution(SensorMotionFit<4>* fit)
{
  Eigen::Matrix<double, 7, 1> flip = Eigen::Matrix<double, 7, 1>::Ones();
  if (fit->intrinsic(kAxisLength) < 0.0) {
    fit->intrinsic(kTractionScale) = -fit->intrinsic(kTractionScale);
    fit->intrinsic(kAxisLength) = -fit->intrinsic(kAxisLength);
    fit->T_base_sensor = Pose2(-fit->T_base_sensor.x(), -fit->T_base_sensor.y(),
                               normalizeAngle(fit->T_base_sensor.theta() + M_PI));
    flip(kTractionScale) = -flip(kTractionScale);
    flip(kAxisLength) = -1.0;
    flip(4) = flip(5) = -1.0;
  }
  if (fit->intrinsic(kTractionScale) < 0.0) {
    fit->intrinsic(kTractionScale) = -fit->intrinsic(kTractionScale);
    fit->intrinsic(kSteeringOffset) = normalizeAngle(fit->intrinsic(kSteeringOffset) + M_PI);
    flip(kTractionScale) = -flip(kTractionScale);
  }
  fit->covariance = flip.asDiagonal() * fit->covariance * flip.asDiagonal();
}

/// Copies the solver's solution and its run into `result` (which holds the start values), with
/// the residuals after the fit, over all pairs and over the inliers, and the parameter rows.
void reportTricycleFit(const std::vector<MotionPair>& pairs, const TricycleEncoderLayout& layout,
                       const SensorMotionFit<4>& fit, TricycleCalibrationResult* result)
{
  result->solve_time_s = fit.solve_time_s;
  result->iterations = fit.iterations;
  result->converged = fit.converged;
  result->termination = fit.termination;
  result->calibrated = TricycleParameters::fromVectors(fit.intrinsic, fit.T_base_sensor.vector());
  result->after = tricycleResidualRms(pairs, layout, result->calibrated);
  std::vector<MotionPair> inliers;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (fit.inlier[i])
      inliers.push_back(pairs[i]);
  }
  result->outlier_count = fit.outliers;
  result->gross_outliers = fit.gross_outliers;
  result->starts = fit.starts;
  result->starts_agreed = fit.starts_agreed;
  result->after_inliers = tricycleResidualRms(inliers, layout, result->calibrated);
  result->chi2_per_dof = fit.chi2_per_dof;
  result->covariance = fit.covariance;
  result->covariance_available = fit.covariance_available;
  result->estimates = makeEstimates(result->initial, result->calibrated, result->covariance,
                                    result->covariance_available);
}

}  // namespace

ObservabilityHints tricycleObservabilityHints()
{
  ObservabilityHints hints;
  hints.unobservable_without_turning = "steering_scale, axis_length and sensor_y";
  hints.confused_by_one_way_turns = "steering_offset cannot be separated from steering_scale";
  hints.relative_parameters = tricycleParameters().relative;
  return hints;
}

TricycleCalibrationResult calibrateTricycle(const std::vector<MotionPair>& pairs,
                                            const TricycleEncoderLayout& layout,
                                            const TricycleParameters& initial,
                                            const TricycleCalibrationOptions& options)
{
  validate(options);
  requireEnoughPairs(pairs, 7, "tricycle calibration",
                     "record a longer drive or shorten the keyframe interval");
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2) {
      throw std::invalid_argument("every pair needs at least two encoder samples");
    }
  }
  validateStartValues(initial);

  TricycleCalibrationResult result;
  result.initial = initial;
  result.pair_count = pairs.size();
  result.before = tricycleResidualRms(pairs, layout, initial);
  SensorMotionFit<4> fit = fitSensorMotion<TricycleKinematics>(
      pairs, layout, initial.kinematicVector(), initial.T_base_sensor,
      sensorMotionFitOptions(options.huber_threshold, options.max_iterations, options.yaw_starts));
  keepPhysicalTricycleSolution(&fit);
  reportTricycleFit(pairs, layout, fit, &result);
  result.warnings =
      observabilityWarnings(pairs, result.estimates, result.covariance, result.covariance_available,
                            tricycleObservabilityHints(), &result.notes);
  return result;
}

}  // namespace odometry_calibration
