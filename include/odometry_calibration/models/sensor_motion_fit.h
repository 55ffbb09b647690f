// The least-squares machinery shared by the parametric models (tricycle seed sections 3-5;
// the same structure as the CMLE of Censi et al. T-RO 2013): intrinsic parameters of a
// kinematic model plus the sensor pose T_base_sensor, fitted to keyframe pairs by minimising
// the whitened SE(2) error e = Z^-1 * (T_bs^-1 * Delta_base * T_bs) under a Huber loss with
// Ceres (Levenberg-Marquardt, automatic derivatives, SE(2) manifold for the pose).
//
// A kinematic model plugs in as a type with
//   using Layout = ...;                           // where its joints are
//   static constexpr int kIntrinsics = N;         // number of intrinsic parameters
//   template <typename T> static Pose2T<T> integrate(const T* intrinsic, const Layout&,
//                                                    const std::vector<EncoderSample>&);
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/se2_manifold.h"

namespace odometry_calibration {

/// Cost functor for one pair: parameter blocks are the intrinsics and the sensor pose
/// (x, y, theta); the residual is the pair's whitened SE(2) error (3 values).
template <class Kinematics>
class SensorMotionResidual
{
public:
  /// Keeps a reference to `pair`, which must outlive the functor. `noise_scale` multiplies
  /// the pair's standard deviations (a robust estimate of how mis-scaled they are).
  SensorMotionResidual(const MotionPair& pair, const typename Kinematics::Layout& layout,
                       double noise_scale = 1.0)
      : pair_(pair), layout_(layout)
  {
    // L^-1 with covariance = L L^T, so that |L^-1 e|^2 = e^T Sigma^-1 e.
    const Eigen::Matrix3d lower = pair.covariance.llt().matrixL();
    sqrt_information_ = lower.inverse() / noise_scale;
  }

  template <typename T>
  bool operator()(const T* intrinsic, const T* sensor_pose, T* residual) const
  {
    const Pose2T<T> T_base_sensor(sensor_pose[0], sensor_pose[1], sensor_pose[2]);
    const Pose2T<T> base_motion = Kinematics::integrate(intrinsic, layout_, pair_.encoder_samples);
    const Eigen::Matrix<T, 3, 1> error =
        boxMinus(sensorMotionFromBodyMotion(T_base_sensor, base_motion),
                 pair_.sensor_motion.template cast<T>());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

private:
  const MotionPair& pair_;
  typename Kinematics::Layout layout_;
  Eigen::Matrix3d sqrt_information_;
};

/// Options of the shared solver.
struct SensorMotionFitOptions
{
  double huber_threshold = 3.0;  ///< on a pair's whitened error norm [sigma]; <= 0: none
  int max_iterations = 500;      ///< Levenberg-Marquardt iteration cap (per solve)
  /// Global starts: the sensor yaw is started at this many evenly spaced angles, the first being
  /// the given start (every 360/n degrees), each solved on at most kScreeningPairs pairs; the
  /// full fit starts from the best of them. 1 (or less): only the given start.
  int yaw_starts = 8;
  /// Whitened error norm beyond which a pair counts as a gross outlier (reported as rejected:
  /// its Huber weight is below huber_threshold / gross_threshold) [sigma].
  double gross_threshold = 5.0;
  /// Rescale the pairs' covariances by a robust estimate of the residual spread (median
  /// whitened error norm against that of unit Gaussian noise) and solve again, so that the
  /// Huber threshold means "n sigma of the actual noise" even when the supplied covariances
  /// (e.g. a scan matcher's) are over- or under-confident.
  bool estimate_noise_scale = true;
};

/// The solution, with everything a report needs.
template <int N>
struct SensorMotionFit
{
  Eigen::Matrix<double, N, 1> intrinsic;
  Pose2 T_base_sensor;
  /// Covariance of (intrinsics, x, y, theta), scaled by chi2_per_dof of the inliers (with
  /// the noise scale applied).
  Eigen::Matrix<double, N + 3, N + 3> covariance = Eigen::Matrix<double, N + 3, N + 3>::Zero();
  bool covariance_available = false;
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
  std::vector<bool> inlier;        ///< per pair: whitened error within the Huber threshold
  double noise_scale = 1.0;        ///< factor applied to the pairs' sigmas (estimate_noise_scale)
  std::size_t outliers = 0;        ///< pairs beyond the Huber threshold (down-weighted)
  std::size_t gross_outliers = 0;  ///< of those, pairs beyond gross_threshold
  int iterations = 0;
  int starts = 1;         ///< starts tried (yaw_starts)
  int starts_agreed = 1;  ///< starts that reached the best minimum (within 1e-4 of its cost)
  bool converged = false;
  std::string termination;
  double solve_time_s = 0.0;
};

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

/// Adds one residual per pair to `problem`: the pair's whitened SE(2) error
/// (SensorMotionResidual, its covariance scaled by `noise_scale`) under a Huber loss when
/// `huber_threshold` > 0, on the blocks `intrinsic` (Kinematics::kIntrinsics values) and
/// `sensor_pose` (x, y, theta, on the SE(2) manifold).
template <class Kinematics>
void addSensorMotionResiduals(ceres::Problem& problem, const std::vector<MotionPair>& pairs,
                              const typename Kinematics::Layout& layout, double huber_threshold,
                              double noise_scale, double* intrinsic, double* sensor_pose)
{
  using Residual = SensorMotionResidual<Kinematics>;
  for (const MotionPair& pair : pairs) {
    auto* cost = new ceres::AutoDiffCostFunction<Residual, 3, Kinematics::kIntrinsics, 3>(
        new Residual(pair, layout, noise_scale));
    ceres::LossFunction* loss =
        huber_threshold > 0.0 ? new ceres::HuberLoss(huber_threshold) : nullptr;
    problem.AddResidualBlock(cost, loss, intrinsic, sensor_pose);
  }
  problem.SetManifold(sensor_pose, newSe2Manifold());
}

/// RMS of the SE(2) errors of the model's predictions over `pairs` (those with `keep[i]` when
/// `keep` is given); per axis into `per_axis` and the errors' second moment (the per-pair
/// spread a prediction's covariance reports) into `spread`, when given.
template <class Kinematics>
ResidualRms sensorMotionResidualRms(const std::vector<MotionPair>& pairs,
                                    const typename Kinematics::Layout& layout,
                                    const double* intrinsic, const Pose2& T_base_sensor,
                                    const std::vector<bool>* keep = nullptr,
                                    Eigen::Vector3d* per_axis = nullptr,
                                    Eigen::Matrix3d* spread = nullptr)
{
  ResidualRms rms;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (keep && !(*keep)[i])
      continue;
    const Pose2 base = Kinematics::integrate(intrinsic, layout, pairs[i].encoder_samples);
    const Eigen::Vector3d e =
        boxMinus(sensorMotionFromBodyMotion(T_base_sensor, base), pairs[i].sensor_motion);
    sum += e.cwiseProduct(e);
    outer += e * e.transpose();
    ++rms.count;
  }
  if (rms.count > 0) {
    const double n = static_cast<double>(rms.count);
    rms.translation_m = std::sqrt((sum(0) + sum(1)) / n);
    rms.rotation_rad = std::sqrt(sum(2) / n);
    if (per_axis)
      *per_axis = (sum / n).cwiseSqrt();
    if (spread)
      *spread = outer / n;
  }
  return rms;
}

/// The solve of fitSensorMotionFrom: the problem of its last solve (which the covariance is
/// computed on), that solve's summary, the iterations of all solves and the noise scale used.
struct SensorMotionSolve
{
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
  int iterations = 0;
  double noise_scale = 1.0;
};

/// The robust noise scale of a solution: the median whitened error norm of the pairs against
/// that of unit Gaussian noise (3-D: sqrt(chi2_3 median 2.366) = 1.538), at least 1e-6.
template <class Kinematics>
double sensorMotionNoiseScale(const std::vector<MotionPair>& pairs,
                              const typename Kinematics::Layout& layout, const double* intrinsic,
                              const double* sensor_pose)
{
  std::vector<double> norms;
  for (const MotionPair& pair : pairs) {
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pair, layout)(intrinsic, sensor_pose, whitened.data());
    norms.push_back(whitened.norm());
  }
  std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
  return std::max(norms[norms.size() / 2] / 1.538, 1e-6);
}

/// Solves for the blocks `intrinsic` and `sensor_pose` (start values in, solution out): a first
/// solve with the supplied covariances; then, if options.estimate_noise_scale and there are at
/// least 10 pairs, a second one with them rescaled by sensorMotionNoiseScale at the first
/// solution.
template <class Kinematics>
SensorMotionSolve solveSensorMotion(const std::vector<MotionPair>& pairs,
                                    const typename Kinematics::Layout& layout,
                                    const SensorMotionFitOptions& options, double* intrinsic,
                                    double* sensor_pose)
{
  SensorMotionSolve solve;
  auto build = [&]() {
    solve.problem = std::make_unique<ceres::Problem>();
    addSensorMotionResiduals<Kinematics>(*solve.problem, pairs, layout, options.huber_threshold,
                                         solve.noise_scale, intrinsic, sensor_pose);
  };
  build();
  const ceres::Solver::Options solver_options =
      sensorFitSolverOptions(options.max_iterations, 1e-12, 1e-12);
  ceres::Solve(solver_options, solve.problem.get(), &solve.summary);
  solve.iterations = static_cast<int>(solve.summary.iterations.size()) - 1;
  if (options.estimate_noise_scale && std::isfinite(solve.summary.final_cost) &&
      pairs.size() >= 10) {
    solve.noise_scale = sensorMotionNoiseScale<Kinematics>(pairs, layout, intrinsic, sensor_pose);
    build();
    ceres::Solve(solver_options, solve.problem.get(), &solve.summary);
    solve.iterations += static_cast<int>(solve.summary.iterations.size()) - 1;
  }
  return solve;
}

/// Marks each pair an inlier when its whitened error (noise scale applied) is within the Huber
/// threshold, counts the outliers and the gross ones among them, and sets chi2_per_dof from the
/// inliers' chi^2 (3 per pair less the N + 3 parameters).
template <class Kinematics>
void classifySensorMotionPairs(const std::vector<MotionPair>& pairs,
                               const typename Kinematics::Layout& layout,
                               const SensorMotionFitOptions& options, const double* intrinsic,
                               const double* sensor_pose,
                               SensorMotionFit<Kinematics::kIntrinsics>* fit)
{
  constexpr int N = Kinematics::kIntrinsics;
  double chi2_inliers = 0.0;
  std::size_t inlier_count = 0;
  for (const MotionPair& pair : pairs) {
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pair, layout, fit->noise_scale)(intrinsic, sensor_pose,
                                                                     whitened.data());
    const double chi2 = whitened.squaredNorm();
    const bool is_inlier =
        options.huber_threshold <= 0.0 || chi2 <= options.huber_threshold * options.huber_threshold;
    fit->inlier.push_back(is_inlier);
    if (is_inlier) {
      chi2_inliers += chi2;
      ++inlier_count;
    } else if (chi2 > options.gross_threshold * options.gross_threshold) {
      ++fit->gross_outliers;
    }
  }
  fit->outliers = pairs.size() - inlier_count;
  const double dof = 3.0 * static_cast<double>(inlier_count) - (N + 3);
  if (dof > 0.0)
    fit->chi2_per_dof = chi2_inliers / dof;
}

/// Beyond this magnitude a Jacobian entry is no measurement (a start or a datum of 1e308
/// overflowing the prediction): J^T J would overflow too.
constexpr double kMaxCovarianceJacobianEntry = 1e100;

/// Whether `problem`'s Jacobian at its parameters' values can be handed to an SVD: every entry
/// finite and below kMaxCovarianceJacobianEntry. Eigen's SVD inside ceres::Covariance crashes
/// (SIGSEGV) on one that is not, where no exception can be caught (issue 32).
inline bool covarianceComputable(ceres::Problem& problem)
{
  double cost = 0.0;
  ceres::CRSMatrix jacobian;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &jacobian) ||
      !std::isfinite(cost))
    return false;
  return std::all_of(jacobian.values.begin(), jacobian.values.end(), [](double entry) {
    return std::isfinite(entry) && std::abs(entry) < kMaxCovarianceJacobianEntry;
  });
}

/// The covariance of (intrinsics, x, y, theta) at the solution of `problem` in the parameters'
/// own coordinates, scaled by chi2_per_dof when that is known, into `fit`. DENSE_SVD with
/// null_space_rank 0 refuses a rank-deficient problem instead of inventing a number for an
/// unobservable direction: covariance_available stays false then, as it does when the
/// Jacobian cannot be handed to the SVD (covarianceComputable).
template <int N>
void sensorMotionCovariance(ceres::Problem& problem, const double* intrinsic,
                            const double* sensor_pose, SensorMotionFit<N>* fit)
{
  if (!covarianceComputable(problem))
    return;
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.null_space_rank = 0;
  covariance_options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance covariance(covariance_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {
      {intrinsic, intrinsic}, {sensor_pose, sensor_pose}, {intrinsic, sensor_pose}};
  if (!covariance.Compute(blocks, &problem))
    return;
  Eigen::Matrix<double, N, N, Eigen::RowMajor> kk;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> ss;
  Eigen::Matrix<double, N, 3, Eigen::RowMajor> ks;
  covariance.GetCovarianceBlock(intrinsic, intrinsic, kk.data());
  covariance.GetCovarianceBlock(sensor_pose, sensor_pose, ss.data());
  covariance.GetCovarianceBlock(intrinsic, sensor_pose, ks.data());
  fit->covariance.template topLeftCorner<N, N>() = kk;
  fit->covariance.template bottomRightCorner<3, 3>() = ss;
  fit->covariance.template topRightCorner<N, 3>() = ks;
  fit->covariance.template bottomLeftCorner<3, N>() = ks.transpose();
  if (std::isfinite(fit->chi2_per_dof))
    fit->covariance *= fit->chi2_per_dof;
  // No residual at all (e.g. no motion: every prediction is zero) measures nothing.
  fit->covariance_available =
      fit->covariance.allFinite() && fit->covariance.diagonal().minCoeff() > 0.0;
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
  std::vector<SensorMotionStart<N>> starts;
  for (int k = 0; k < options.yaw_starts; ++k) {
    const double yaw = normalizeAngle(initial_T_base_sensor.theta() +
                                      2.0 * M_PI * static_cast<double>(k) / options.yaw_starts);
    starts.push_back(screenSensorMotionStart<Kinematics>(
        screening, layout, initial_intrinsic,
        Eigen::Vector3d(initial_T_base_sensor.x(), initial_T_base_sensor.y(), yaw), options));
  }
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
