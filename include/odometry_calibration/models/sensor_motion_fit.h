// The least-squares machinery shared by the parametric models (tricycle seed sections 3-5;
// the same structure as the CMLE of Censi et al. T-RO 2013): intrinsic parameters of a
// kinematic model plus the sensor pose T_base_sensor, fitted to keyframe pairs by minimising
// the whitened SE(2) error e = Z^-1 * (T_bs^-1 * Delta_base * T_bs) under a Huber loss with
// Ceres (Levenberg-Marquardt, automatic derivatives, SE(2) manifold for the pose).
//
// Several sensors at once (a front and a rear laser): one set of intrinsics and one
// pose per sensor, each pair tagged with its sensor (`SensorPairs`) and weighted by its own
// covariance, the covariances of each sensor rescaled by that sensor's own robust noise scale.
// The one-sensor functions below are the several-sensor ones with every pair of sensor 0.
//
// The residual, the result, the pair classes and the covariance live in their own headers
// (sensor_motion_residual.h, sensor_motion_fit_result.h, sensor_motion_pair_classes.h,
// sensor_motion_covariance.h); this one holds the solves.
#pragma once

#include <chrono>
#include <cmath>
#include <cstddef>
#include <future>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/sensor_motion_covariance.h"
#include "odometry_calibration/models/sensor_motion_fit_result.h"
#include "odometry_calibration/models/sensor_motion_pair_classes.h"
#include "odometry_calibration/models/sensor_motion_residual.h"

namespace odometry_calibration {

/// The solver of the sensor-motion fits: Levenberg-Marquardt with dense QR on one thread, at most
/// `max_iterations` per solve; `tolerance` on the relative cost change and the parameter step,
/// `gradient_tolerance` on the gradient.
inline ceres::Solver::Options sensorFitSolverOptions(int max_iterations, double tolerance,
                                                     double gradient_tolerance)
{
  ceres::Solver::Options solver_options;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = max_iterations;
  solver_options.function_tolerance = tolerance;
  solver_options.gradient_tolerance = gradient_tolerance;
  solver_options.parameter_tolerance = tolerance;
  solver_options.num_threads = 1;
  return solver_options;
}

/// The solve of fitSensorMotionFrom: the problem of its last solve (which the covariance is
/// computed on), that solve's summary, the iterations of all solves and the noise scale used.
struct SensorMotionSolve
{
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
  int iterations = 0;
  double noise_scale = 1.0;          ///< sensor 0's
  std::vector<double> noise_scales;  ///< each sensor's
};

/// Solves for the blocks `intrinsic` and `sensor_poses` (start values in, solution out): a first
/// solve with the supplied covariances; then, if options.estimate_noise_scale and there are at
/// least 10 pairs, a second one with each sensor's rescaled by its sensorMotionNoiseScales at
/// the first solution.
template <class Kinematics>
SensorMotionSolve solveSensorMotion(const SensorPairs& pairs,
                                    const typename Kinematics::Layout& layout,
                                    const SensorMotionFitOptions& options, double* intrinsic,
                                    const std::vector<double*>& sensor_poses)
{
  SensorMotionSolve solve;
  solve.noise_scales.assign(sensor_poses.size(), 1.0);
  auto build = [&]() {
    solve.problem = std::make_unique<ceres::Problem>();
    addSensorMotionResiduals<Kinematics>(*solve.problem, pairs, layout, options.huber_threshold,
                                         solve.noise_scales, intrinsic, sensor_poses);
  };
  build();
  const ceres::Solver::Options solver_options =
      sensorFitSolverOptions(options.max_iterations, 1e-12, 1e-12);
  ceres::Solve(solver_options, solve.problem.get(), &solve.summary);
  solve.iterations = static_cast<int>(solve.summary.iterations.size()) - 1;
  if (options.estimate_noise_scale && std::isfinite(solve.summary.final_cost) &&
      pairs.pairs.size() >= 10) {
    solve.noise_scales = sensorMotionNoiseScales<Kinematics>(
        pairs, layout, intrinsic,
        std::vector<const double*>(sensor_poses.begin(), sensor_poses.end()));
    solve.noise_scale = solve.noise_scales[0];
    build();
    ceres::Solve(solver_options, solve.problem.get(), &solve.summary);
    solve.iterations += static_cast<int>(solve.summary.iterations.size()) - 1;
  }
  return solve;
}

/// solveSensorMotion for the pairs of one sensor (pose `sensor_pose`).
template <class Kinematics>
SensorMotionSolve solveSensorMotion(const std::vector<MotionPair>& pairs,
                                    const typename Kinematics::Layout& layout,
                                    const SensorMotionFitOptions& options, double* intrinsic,
                                    double* sensor_pose)
{
  return solveSensorMotion<Kinematics>(SensorPairs{pairs, {}}, layout, options, intrinsic,
                                       {sensor_pose});
}

/// Fits the intrinsics and the sensor pose from one start (no global starts): solveSensorMotion,
/// then the inliers (classifySensorMotionPairs) and the covariance (sensorMotionCovariance) at
/// the solution. A solution that is not finite is reported as not converged, without
/// covariance and with every pair an outlier.
template <class Kinematics>
SensorMotionFit<Kinematics::kIntrinsics> fitSensorMotionFrom(
    const std::vector<MotionPair>& pairs, const typename Kinematics::Layout& layout,
    const Eigen::Matrix<double, Kinematics::kIntrinsics, 1>& initial_intrinsic,
    const Pose2& initial_T_base_sensor, const SensorMotionFitOptions& options)
{
  constexpr int N = Kinematics::kIntrinsics;
  SensorMotionFit<N> fit;
  Eigen::Matrix<double, N, 1> intrinsic = initial_intrinsic;
  Eigen::Vector3d sensor_pose = initial_T_base_sensor.vector();
  const auto start = std::chrono::steady_clock::now();
  const SensorMotionSolve solve =
      solveSensorMotion<Kinematics>(pairs, layout, options, intrinsic.data(), sensor_pose.data());
  const ceres::Solver::Summary& summary = solve.summary;
  fit.noise_scale = solve.noise_scale;
  fit.solve_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fit.iterations = solve.iterations;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.termination = summary.message;
  if (!std::isfinite(summary.final_cost) || !intrinsic.allFinite() || !sensor_pose.allFinite()) {
    // A degenerate model (e.g. a length driven to zero): report failure, no covariance.
    fit.converged = false;
    fit.termination =
        "the solution is not finite (" + summary.message + "): check the start values and the data";
    fit.intrinsic = intrinsic;
    fit.T_base_sensor = Pose2(sensor_pose(0), sensor_pose(1), sensor_pose(2));
    fit.inlier.assign(pairs.size(), false);
    fit.outliers = pairs.size();
    return fit;
  }
  sensor_pose(2) = normalizeAngle(sensor_pose(2));
  classifySensorMotionPairs<Kinematics>(pairs, layout, options, intrinsic.data(),
                                        sensor_pose.data(), &fit);
  sensorMotionCovariance(*solve.problem, intrinsic.data(), sensor_pose.data(), &fit);
  fit.intrinsic = intrinsic;
  fit.T_base_sensor = Pose2(sensor_pose(0), sensor_pose(1), sensor_pose(2));
  return fit;
}

/// Pairs a global start is screened on at most (evenly spaced through the set).
constexpr std::size_t kScreeningPairs = 200;

/// One start of the screening: the solution on the screening pairs and its robust cost.
template <int N>
struct SensorMotionStart
{
  Eigen::Matrix<double, N, 1> intrinsic;
  Eigen::Vector3d sensor_pose;
  double cost = std::numeric_limits<double>::infinity();
};

/// Solves from one start on `pairs` with the supplied covariances (no noise scale, no
/// covariance): the cheap first stage of the global starts.
template <class Kinematics>
SensorMotionStart<Kinematics::kIntrinsics> screenSensorMotionStart(
    const std::vector<MotionPair>& pairs, const typename Kinematics::Layout& layout,
    const Eigen::Matrix<double, Kinematics::kIntrinsics, 1>& initial_intrinsic,
    const Eigen::Vector3d& initial_sensor_pose, const SensorMotionFitOptions& options)
{
  constexpr int N = Kinematics::kIntrinsics;
  SensorMotionStart<N> start;
  start.intrinsic = initial_intrinsic;
  start.sensor_pose = initial_sensor_pose;
  ceres::Problem problem;
  addSensorMotionResiduals<Kinematics>(problem, pairs, layout, options.huber_threshold, 1.0,
                                       start.intrinsic.data(), start.sensor_pose.data());
  // Only the basin matters here: the full fit polishes the best start.
  const ceres::Solver::Options solver_options =
      sensorFitSolverOptions(options.max_iterations, 1e-8, 1e-10);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (std::isfinite(summary.final_cost) && start.intrinsic.allFinite() &&
      start.sensor_pose.allFinite()) {
    start.cost = summary.final_cost;
  }
  return start;
}

/// Fits the intrinsics and the sensor pose. With options.yaw_starts > 1 (global starts), the
/// sensor yaw is started at yaw_starts evenly spaced angles from the given one, each solved on a
/// subset of at most kScreeningPairs pairs; the full fit (fitSensorMotionFrom) starts from the
/// screening solution of least cost. `starts_agreed` counts the starts whose screening cost is
/// within 1e-4 (relative) of the best: a low count says the cost has several minima and the
/// start values matter. Pairs need >= 2 samples.
template <class Kinematics>
SensorMotionFit<Kinematics::kIntrinsics> fitSensorMotion(
    const std::vector<MotionPair>& pairs, const typename Kinematics::Layout& layout,
    const Eigen::Matrix<double, Kinematics::kIntrinsics, 1>& initial_intrinsic,
    const Pose2& initial_T_base_sensor, const SensorMotionFitOptions& options)
{
  constexpr int N = Kinematics::kIntrinsics;
  if (options.yaw_starts <= 1 || pairs.empty()) {
    return fitSensorMotionFrom<Kinematics>(pairs, layout, initial_intrinsic, initial_T_base_sensor,
                                           options);
  }
  const auto start_time = std::chrono::steady_clock::now();
  std::vector<MotionPair> screening;
  const std::size_t stride = (pairs.size() + kScreeningPairs - 1) / kScreeningPairs;
  for (std::size_t i = 0; i < pairs.size(); i += stride)
    screening.push_back(pairs[i]);
  std::vector<SensorMotionStart<N>> starts(static_cast<std::size_t>(options.yaw_starts));
  auto screen = [&](int first, int end) {
    for (int k = first; k < end; ++k) {
      const double yaw = normalizeAngle(initial_T_base_sensor.theta() +
                                        2.0 * M_PI * static_cast<double>(k) / options.yaw_starts);
      starts[static_cast<std::size_t>(k)] = screenSensorMotionStart<Kinematics>(
          screening, layout, initial_intrinsic,
          Eigen::Vector3d(initial_T_base_sensor.x(), initial_T_base_sensor.y(), yaw), options);
    }
  };
  // The starts are independent solves, each the same on any thread: the second half runs on
  // another one (half the screening's wall time on two cores, the same fit; at get() on this
  // one when no thread can be made).
  const int half = options.yaw_starts / 2;
  std::future<void> second_half =
      std::async(std::launch::async | std::launch::deferred, screen, half, options.yaw_starts);
  screen(0, half);
  second_half.get();
  std::size_t best = 0;
  for (std::size_t k = 1; k < starts.size(); ++k) {
    if (starts[k].cost < starts[best].cost)
      best = k;
  }
  int agreed = 0;
  for (const SensorMotionStart<N>& start : starts) {
    if (start.cost <= starts[best].cost * (1.0 + 1e-4) + 1e-12)
      ++agreed;
  }
  SensorMotionFit<N> fit;
  if (std::isfinite(starts[best].cost)) {
    const Eigen::Vector3d& pose = starts[best].sensor_pose;
    fit = fitSensorMotionFrom<Kinematics>(pairs, layout, starts[best].intrinsic,
                                          Pose2(pose(0), pose(1), pose(2)), options);
  } else {
    fit = fitSensorMotionFrom<Kinematics>(pairs, layout, initial_intrinsic, initial_T_base_sensor,
                                          options);
  }
  fit.starts = options.yaw_starts;
  fit.starts_agreed = agreed;
  fit.solve_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return fit;
}

}  // namespace odometry_calibration
