// The covariance of a sensor-motion fit's parameters (intrinsics, then each sensor's pose) from
// Ceres at the solution, guarded against Jacobians no SVD can take.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>

#include "odometry_calibration/models/sensor_motion_fit_result.h"

namespace odometry_calibration {

/// Beyond this magnitude a Jacobian entry is no measurement (a start or a datum of 1e308
/// overflowing the prediction): J^T J would overflow too.
constexpr double kMaxCovarianceJacobianEntry = 1e100;

/// Whether `problem`'s Jacobian at its parameters' values can be handed to an SVD: every entry
/// finite and below kMaxCovarianceJacobianEntry. Eigen's SVD inside ceres::Covariance crashes
/// (SIGSEGV) on one that is not, where no exception can be caught.
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

}  // namespace odometry_calibration
