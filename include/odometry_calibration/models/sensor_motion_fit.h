// The least-squares machinery shared by the parametric models (tricycle seed sections 3-5;
// the same structure as the CMLE of Censi et al. T-RO 2013): intrinsic parameters of a
// kinematic model plus the sensor pose T_base_sensor, fitted to keyframe pairs by minimising
// the whitened SE(2) error e = Z^-1 * (T_bs^-1 * Delta_base * T_bs) under a Huber loss with
// Ceres (Levenberg-Marquardt, automatic derivatives, SE(2) manifold for the pose).
//
// Several sensors at once (issue 35: a front and a rear laser): one set of intrinsics and one
// pose per sensor, each pair tagged with its sensor (`SensorPairs`) and weighted by its own
// covariance, the covariances of each sensor rescaled by that sensor's own robust noise scale.
// The one-sensor functions below are the several-sensor ones with every pair of sensor 0.
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

/// Pairs of one or several sensors: `sensor[i]` is pair i's sensor (0, 1, ...), an empty
/// `sensor` puts every pair on sensor 0. The pairs are referenced, not copied.
struct SensorPairs
{
  const std::vector<MotionPair>& pairs;
  std::vector<std::size_t> sensor;

  std::size_t sensorOf(std::size_t i) const { return sensor.empty() ? 0 : sensor[i]; }
};

/// Adds one residual per pair to `problem` on the intrinsics and its sensor's pose
/// (`sensor_poses[sensorOf(i)]`, 3 values each on the SE(2) manifold), its covariance scaled by
/// its sensor's `noise_scales` entry: the several-sensor form of the function below.
template <class Kinematics>
void addSensorMotionResiduals(ceres::Problem& problem, const SensorPairs& pairs,
                              const typename Kinematics::Layout& layout, double huber_threshold,
                              const std::vector<double>& noise_scales, double* intrinsic,
                              const std::vector<double*>& sensor_poses)
{
  using Residual = SensorMotionResidual<Kinematics>;
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    auto* cost = new ceres::AutoDiffCostFunction<Residual, 3, Kinematics::kIntrinsics, 3>(
        new Residual(pairs.pairs[i], layout, noise_scales[sensor]));
    ceres::LossFunction* loss =
        huber_threshold > 0.0 ? new ceres::HuberLoss(huber_threshold) : nullptr;
    problem.AddResidualBlock(cost, loss, intrinsic, sensor_poses[sensor]);
  }
  for (double* sensor_pose : sensor_poses) {
    if (problem.HasParameterBlock(sensor_pose))
      problem.SetManifold(sensor_pose, newSe2Manifold());
  }
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
  addSensorMotionResiduals<Kinematics>(problem, SensorPairs{pairs, {}}, layout, huber_threshold,
                                       {noise_scale}, intrinsic, {sensor_pose});
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
  double noise_scale = 1.0;          ///< sensor 0's
  std::vector<double> noise_scales;  ///< each sensor's
};

/// The robust noise scale of each sensor (sensorMotionNoiseScale over that sensor's pairs; 1
/// for a sensor without pairs).
template <class Kinematics>
std::vector<double> sensorMotionNoiseScales(const SensorPairs& pairs,
                                            const typename Kinematics::Layout& layout,
                                            const double* intrinsic,
                                            const std::vector<const double*>& sensor_poses)
{
  std::vector<std::vector<double>> norms(sensor_poses.size());
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pairs.pairs[i], layout)(intrinsic, sensor_poses[sensor],
                                                             whitened.data());
    norms[sensor].push_back(whitened.norm());
  }
  std::vector<double> scales(sensor_poses.size(), 1.0);
  for (std::size_t s = 0; s < norms.size(); ++s) {
    if (norms[s].empty())
      continue;
    std::vector<double>& n = norms[s];
    std::nth_element(n.begin(), n.begin() + n.size() / 2, n.end());
    scales[s] = std::max(n[n.size() / 2] / 1.538, 1e-6);
  }
  return scales;
}

/// The robust noise scale of a solution: the median whitened error norm of the pairs against
/// that of unit Gaussian noise (3-D: sqrt(chi2_3 median 2.366) = 1.538), at least 1e-6.
template <class Kinematics>
double sensorMotionNoiseScale(const std::vector<MotionPair>& pairs,
                              const typename Kinematics::Layout& layout, const double* intrinsic,
                              const double* sensor_pose)
{
  return sensorMotionNoiseScales<Kinematics>(SensorPairs{pairs, {}}, layout, intrinsic,
                                             {sensor_pose})[0];
}

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

/// The pairs of a fit sorted by their whitened errors: inliers, and per sensor the outliers and
/// the gross ones among them; chi2_per_dof of the inliers (NaN without degrees of freedom).
struct SensorPairClasses
{
  std::vector<bool> inlier;
  std::vector<std::size_t> outliers, gross_outliers;
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
};

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

/// The several-sensor form of the function below: each pair whitened with its sensor's noise
/// scale, the degrees of freedom 3 per inlier less the N + 3 S parameters.
template <class Kinematics>
SensorPairClasses classifySensorMotionPairs(const SensorPairs& pairs,
                                            const typename Kinematics::Layout& layout,
                                            const SensorMotionFitOptions& options,
                                            const double* intrinsic,
                                            const std::vector<const double*>& sensor_poses,
                                            const std::vector<double>& noise_scales)
{
  constexpr int N = Kinematics::kIntrinsics;
  const std::size_t sensors = sensor_poses.size();
  SensorPairClasses classes;
  classes.outliers.assign(sensors, 0);
  classes.gross_outliers.assign(sensors, 0);
  double chi2_inliers = 0.0;
  std::size_t inlier_count = 0;
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pairs.pairs[i], layout, noise_scales[sensor])(
        intrinsic, sensor_poses[sensor], whitened.data());
    const double chi2 = whitened.squaredNorm();
    const bool is_inlier =
        options.huber_threshold <= 0.0 || chi2 <= options.huber_threshold * options.huber_threshold;
    classes.inlier.push_back(is_inlier);
    if (is_inlier) {
      chi2_inliers += chi2;
      ++inlier_count;
      continue;
    }
    ++classes.outliers[sensor];
    if (chi2 > options.gross_threshold * options.gross_threshold)
      ++classes.gross_outliers[sensor];
  }
  const double dof = 3.0 * static_cast<double>(inlier_count) - (N + 3.0 * sensors);
  if (dof > 0.0)
    classes.chi2_per_dof = chi2_inliers / dof;
  return classes;
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
  const SensorPairClasses classes = classifySensorMotionPairs<Kinematics>(
      SensorPairs{pairs, {}}, layout, options, intrinsic, {sensor_pose}, {fit->noise_scale});
  fit->inlier.insert(fit->inlier.end(), classes.inlier.begin(), classes.inlier.end());
  fit->outliers = classes.outliers[0];
  fit->gross_outliers += classes.gross_outliers[0];
  if (std::isfinite(classes.chi2_per_dof))
    fit->chi2_per_dof = classes.chi2_per_dof;
}

/// The several-sensor form of the function below: the covariance of (the `intrinsics` values,
/// then x, y, theta of each of `sensor_poses`), scaled by `chi2_per_dof` when finite, into
/// `covariance` (left empty when the problem is rank-deficient). Returns whether it is
/// available (finite, every variance positive).
inline bool sensorMotionCovariance(ceres::Problem& problem, const double* intrinsic, int intrinsics,
                                   const std::vector<const double*>& sensor_poses,
                                   double chi2_per_dof, Eigen::MatrixXd* covariance)
{
  if (!covarianceComputable(problem))
    return false;
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.null_space_rank = 0;
  covariance_options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance solver(covariance_options);
  // Block k of the matrix: the intrinsics (k = 0), then the sensors; its first row and size.
  std::vector<const double*> block{intrinsic};
  std::vector<int> first{0}, size{intrinsics};
  for (const double* pose : sensor_poses) {
    block.push_back(pose);
    first.push_back(first.back() + size.back());
    size.push_back(3);
  }
  std::vector<std::pair<const double*, const double*>> wanted = {{intrinsic, intrinsic}};
  for (std::size_t a = 1; a < block.size(); ++a)
    wanted.emplace_back(block[a], block[a]);
  for (std::size_t a = 1; a < block.size(); ++a)
    wanted.emplace_back(intrinsic, block[a]);
  for (std::size_t a = 1; a < block.size(); ++a)
    for (std::size_t b = a + 1; b < block.size(); ++b)
      wanted.emplace_back(block[a], block[b]);
  if (!solver.Compute(wanted, &problem))
    return false;
  covariance->setZero(first.back() + size.back(), first.back() + size.back());
  for (const auto& [row_block, column_block] : wanted) {
    const std::size_t a = std::find(block.begin(), block.end(), row_block) - block.begin();
    const std::size_t b = std::find(block.begin(), block.end(), column_block) - block.begin();
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> part(size[a], size[b]);
    solver.GetCovarianceBlock(row_block, column_block, part.data());
    covariance->block(first[a], first[b], size[a], size[b]) = part;
    if (a != b)
      covariance->block(first[b], first[a], size[b], size[a]) = part.transpose();
  }
  if (std::isfinite(chi2_per_dof))
    *covariance *= chi2_per_dof;
  // No residual at all (e.g. no motion: every prediction is zero) measures nothing.
  return covariance->allFinite() && covariance->diagonal().minCoeff() > 0.0;
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
  Eigen::MatrixXd covariance;
  fit->covariance_available =
      sensorMotionCovariance(problem, intrinsic, N, {sensor_pose}, fit->chi2_per_dof, &covariance);
  if (covariance.rows() == N + 3)
    fit->covariance = covariance;
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
