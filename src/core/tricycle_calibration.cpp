#include "odometry_calibration/models/tricycle_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <ceres/ceres.h>

#include "odometry_calibration/models/se2_manifold.h"
#include "odometry_calibration/models/tricycle_observability.h"
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
  const char* names[] = {"steering_scale", "traction_scale", "axis_length", "steering_offset",
                         "sensor_x",       "sensor_y",       "sensor_theta"};
  const char* units[] = {"-", "m/turn", "m", "rad", "m", "m", "rad"};
  Eigen::Matrix<double, 7, 1> start;
  start << initial.kinematicVector(), initial.T_base_sensor.vector();
  Eigen::Matrix<double, 7, 1> value;
  value << calibrated.kinematicVector(), calibrated.T_base_sensor.vector();
  std::vector<ParameterEstimate> estimates;
  for (int i = 0; i < 7; ++i) {
    const double sigma = covariance_available ? std::sqrt(std::max(0.0, covariance(i, i)))
                                              : std::numeric_limits<double>::quiet_NaN();
    estimates.push_back({names[i], units[i], start(i), value(i), sigma});
  }
  return estimates;
}

}  // namespace

TricycleCalibrationResult calibrateTricycle(const std::vector<MotionPair>& pairs,
                                            const TricycleEncoderLayout& layout,
                                            const TricycleParameters& initial,
                                            const TricycleCalibrationOptions& options)
{
  validate(options);
  if (pairs.size() < 7) {
    throw std::invalid_argument("tricycle calibration needs at least 7 keyframe pairs, got " +
                                std::to_string(pairs.size()) +
                                ": record a longer drive or shorten the keyframe interval");
  }
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2) {
      throw std::invalid_argument("every pair needs at least two encoder samples");
    }
  }

  TricycleCalibrationResult result;
  result.initial = initial;
  result.pair_count = pairs.size();
  result.before = tricycleResidualRms(pairs, layout, initial);

  Eigen::Vector4d kinematic = initial.kinematicVector();
  Eigen::Vector3d sensor_pose = initial.T_base_sensor.vector();

  ceres::Problem problem;
  for (const MotionPair& pair : pairs) {
    auto* cost = new ceres::AutoDiffCostFunction<TricyclePairResidual, 3, 4, 3>(
        new TricyclePairResidual(pair, layout));
    ceres::LossFunction* loss =
        options.huber_threshold > 0.0 ? new ceres::HuberLoss(options.huber_threshold) : nullptr;
    problem.AddResidualBlock(cost, loss, kinematic.data(), sensor_pose.data());
  }
  problem.SetManifold(sensor_pose.data(), newSe2Manifold());

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  const auto start = std::chrono::steady_clock::now();
  ceres::Solve(solver_options, &problem, &summary);
  result.solve_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.termination = summary.message;

  result.calibrated = TricycleParameters::fromVectors(kinematic, sensor_pose);
  sensor_pose = result.calibrated.T_base_sensor.vector();
  result.after = tricycleResidualRms(pairs, layout, result.calibrated);

  // Inliers: pairs whose whitened error stays within the Huber threshold.
  std::vector<MotionPair> inliers;
  double chi2_inliers = 0.0;
  for (const MotionPair& pair : pairs) {
    TricyclePairResidual residual(pair, layout);
    Eigen::Vector3d whitened;
    residual(kinematic.data(), sensor_pose.data(), whitened.data());
    const double chi2 = whitened.squaredNorm();
    if (options.huber_threshold <= 0.0 ||
        chi2 <= options.huber_threshold * options.huber_threshold) {
      inliers.push_back(pair);
      chi2_inliers += chi2;
    }
  }
  result.outlier_count = pairs.size() - inliers.size();
  result.after_inliers = tricycleResidualRms(inliers, layout, result.calibrated);
  const double dof = 3.0 * static_cast<double>(inliers.size()) - 7.0;
  result.chi2_per_dof = dof > 0.0 ? chi2_inliers / dof : std::numeric_limits<double>::quiet_NaN();

  // Parameter covariance at the solution, in the parameters' own coordinates, scaled by the
  // residual spread so that sigma reflects the data rather than the assumed noise.
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.null_space_rank = 0;
  covariance_options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance covariance(covariance_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {
      {kinematic.data(), kinematic.data()},
      {sensor_pose.data(), sensor_pose.data()},
      {kinematic.data(), sensor_pose.data()}};
  if (covariance.Compute(blocks, &problem)) {
    Eigen::Matrix<double, 4, 4, Eigen::RowMajor> kk;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> ss;
    Eigen::Matrix<double, 4, 3, Eigen::RowMajor> ks;
    covariance.GetCovarianceBlock(kinematic.data(), kinematic.data(), kk.data());
    covariance.GetCovarianceBlock(sensor_pose.data(), sensor_pose.data(), ss.data());
    covariance.GetCovarianceBlock(kinematic.data(), sensor_pose.data(), ks.data());
    result.covariance.topLeftCorner<4, 4>() = kk;
    result.covariance.bottomRightCorner<3, 3>() = ss;
    result.covariance.topRightCorner<4, 3>() = ks;
    result.covariance.bottomLeftCorner<3, 4>() = ks.transpose();
    if (std::isfinite(result.chi2_per_dof)) {
      result.covariance *= result.chi2_per_dof;
    }
    result.covariance_available = true;
  }
  result.estimates =
      makeEstimates(initial, result.calibrated, result.covariance, result.covariance_available);
  result.warnings = tricycleObservabilityWarnings(pairs, result);
  return result;
}

}  // namespace odometry_calibration
