// What the parametric sensor-motion models (differential drive, mecanum; skid-steer through the
// differential drive) do around the shared solver (sensor_motion_fit.h), written once: a fit
// from the start values to the model's report (the residuals before and after, the physical one
// of two mirrored solutions, the spread a prediction carries, the parameter rows of the model's
// ParameterLayout) and a prediction h = T_bs^-1 * Delta_base * T_bs.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/parameter_estimates.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/sensor_motion_fit.h"
#include "odometry_calibration/models/sensor_motion_state.h"

namespace odometry_calibration {

/// The shared solver's options from a model's: Huber threshold [sigma], Levenberg-Marquardt
/// iteration cap, global starts of the sensor yaw.
inline SensorMotionFitOptions sensorMotionFitOptions(double huber_threshold, int max_iterations,
                                                     int yaw_starts)
{
  SensorMotionFitOptions options;
  options.huber_threshold = huber_threshold;
  options.max_iterations = max_iterations;
  options.yaw_starts = yaw_starts;
  return options;
}

/// The mirrored solution: all intrinsics negated with the sensor at (-x, -y, theta + pi)
/// predict the same motions (the base motion is conjugated by a half turn); the covariance's
/// blocks between theta and the negated coordinates change sign.
template <int N>
void mirrorSensorMotionFit(SensorMotionFit<N>* fit)
{
  fit->intrinsic = -fit->intrinsic;
  fit->T_base_sensor = Pose2(-fit->T_base_sensor.x(), -fit->T_base_sensor.y(),
                             normalizeAngle(fit->T_base_sensor.theta() + M_PI));
  Eigen::Matrix<double, N + 3, 1> flip = -Eigen::Matrix<double, N + 3, 1>::Ones();
  flip(N + 2) = 1.0;
  fit->covariance = flip.asDiagonal() * fit->covariance * flip.asDiagonal();
}

/// Copies what the solver says about its run into `report`: outliers (rejected: the gross ones;
/// down-weighted: the others), starts, iterations, convergence, time and the sensor pose.
template <int N>
void reportSensorMotionFit(const SensorMotionFit<N>& fit, ModelReport* report)
{
  report->outliers = fit.outliers;
  report->rejected = fit.gross_outliers;
  report->down_weighted = fit.outliers - fit.gross_outliers;
  report->starts = fit.starts;
  report->starts_agreed = fit.starts_agreed;
  report->iterations = fit.iterations;
  report->converged = fit.converged;
  report->termination = fit.termination;
  report->fit_time_s = fit.solve_time_s;
  report->has_extrinsic = true;
  report->T_base_sensor = fit.T_base_sensor;
}

/// What fitParametricModel reports besides the new state.
struct ParametricFit
{
  ModelReport report;                 ///< everything but the observability warnings and notes
  bool covariance_available = false;  ///< the state's covariance is determined
};

/// Fits the intrinsics and the sensor pose of `state` from its current values and reports it as
/// model `model`: the residual RMS at the start and at the solution, the solution mirrored
/// (mirrorSensorMotionFit) when `mirrored(intrinsics)` says it is the unphysical one, the inliers'
/// per-axis RMS, the parameter rows named by `parameters` (intrinsics, then x, y, theta). The
/// solution, its covariance and the inliers' error spread (prediction_covariance, left as it
/// is without an inlier) go to `state`.
template <class Kinematics, class Mirrored>
ParametricFit fitParametricModel(const std::string& model, const std::vector<MotionPair>& pairs,
                                 const typename Kinematics::Layout& layout,
                                 const SensorMotionFitOptions& options,
                                 const ParameterLayout& parameters, Mirrored mirrored,
                                 SensorMotionState<Kinematics::kIntrinsics>* state)
{
  constexpr int N = Kinematics::kIntrinsics;
  const Eigen::Matrix<double, N, 1> start_intrinsic = state->intrinsics;
  const Pose2 start_T_base_sensor = state->T_base_sensor;
  ParametricFit result;
  ModelReport& report = result.report;
  report.model = model;
  report.pairs_used = pairs.size();
  report.before = sensorMotionResidualRms<Kinematics>(pairs, layout, start_intrinsic.data(),
                                                      start_T_base_sensor);
  SensorMotionFit<N> fit =
      fitSensorMotion<Kinematics>(pairs, layout, start_intrinsic, start_T_base_sensor, options);
  if (mirrored(fit.intrinsic))
    mirrorSensorMotionFit(&fit);
  state->intrinsics = fit.intrinsic;
  state->T_base_sensor = fit.T_base_sensor;
  state->covariance = fit.covariance;
  result.covariance_available = fit.covariance_available;
  report.after =
      sensorMotionResidualRms<Kinematics>(pairs, layout, fit.intrinsic.data(), fit.T_base_sensor);
  sensorMotionResidualRms<Kinematics>(pairs, layout, fit.intrinsic.data(), fit.T_base_sensor,
                                      &fit.inlier, &report.residual_rms_xytheta,
                                      &state->prediction_covariance);
  reportSensorMotionFit(fit, &report);
  Eigen::Matrix<double, N + 3, 1> start, value;
  start << start_intrinsic, start_T_base_sensor.vector();
  value << fit.intrinsic, fit.T_base_sensor.vector();
  report.parameters = parameterEstimates(parameters.names, parameters.units, start, value,
                                         fit.covariance, fit.covariance_available);
  return result;
}

/// The sensor's predicted motion over `samples`: the base motion of the kinematics at the
/// state's intrinsics seen from the sensor at its T_base_sensor, with its prediction covariance.
template <class Kinematics>
MotionPrediction predictSensorMotion(const SensorMotionState<Kinematics::kIntrinsics>& state,
                                     const typename Kinematics::Layout& layout,
                                     const std::vector<EncoderSample>& samples)
{
  MotionPrediction prediction;
  prediction.mean = sensorMotionFromBodyMotion(
      state.T_base_sensor, Kinematics::integrate(state.intrinsics.data(), layout, samples));
  prediction.covariance = state.prediction_covariance;
  return prediction;
}

}  // namespace odometry_calibration
