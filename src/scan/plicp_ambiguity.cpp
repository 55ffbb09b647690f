#include "odometry_calibration/scan/plicp_ambiguity.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace odometry_calibration {

bool needsAmbiguityCheck(const PlicpResult& result, const PlicpOptions& options)
{
  if (!options.check_ambiguity || !result.valid() || result.covariance.isZero())
    return false;
  if (result.degeneracy.information_ratio < options.ambiguity_max_information_ratio)
    return true;  // near degenerate: a slide along the weak direction may fit as well
  if (result.correspondence_count >= options.ambiguity_max_correspondences)
    return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(
      result.covariance.topLeftCorner<2, 2>());
  return std::sqrt(std::max(eigen.eigenvalues()(1), 0.0)) > options.ambiguity_sigma_m ||
         std::sqrt(std::max(result.covariance(2, 2), 0.0)) > options.ambiguity_sigma_rad;
}

IterationStop backAtSolution(const PlicpResult& best, const PlicpOptions& options)
{
  if (options.ambiguity_return_sigma <= 0.0)
    return nullptr;
  const Pose2 solution = best.T_ref_new;
  const Eigen::Matrix3d information = best.covariance.inverse();
  const double bound_squared = options.ambiguity_return_sigma * options.ambiguity_return_sigma;
  const double trim_floor_m = options.adaptive_trim_floor_m;
  return [solution, information, bound_squared, trim_floor_m](const Pose2& T_ref_new,
                                                              double pose_uncertainty_m) {
    if (pose_uncertainty_m > trim_floor_m)
      return false;  // the next trimming keeps more than at the solution: it may lead elsewhere
    Eigen::Vector3d d = T_ref_new.vector() - solution.vector();
    d(2) = normalizeAngle(d(2));
    return d.dot(information * d) < bound_squared;
  };
}

PlicpResult checkAmbiguity(PlicpResult best, const PlicpOptions& options,
                           const PlicpRematch& rematch)
{
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(best.covariance.topLeftCorner<2, 2>());
  const Eigen::Vector2d weakest = eigen.eigenvectors().col(1);
  const Pose2 solution = best.T_ref_new;
  const IterationStop stop = backAtSolution(best, options);
  std::vector<std::pair<Pose2, PlicpResult>> others;  // (start, converged rematch)
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(options.ambiguity_offset_m * weakest.x(),
                        options.ambiguity_offset_m * weakest.y(), 0.0),
        Eigen::Vector3d(-options.ambiguity_offset_m * weakest.x(),
                        -options.ambiguity_offset_m * weakest.y(), 0.0),
        Eigen::Vector3d(0.0, 0.0, options.ambiguity_offset_rad),
        Eigen::Vector3d(0.0, 0.0, -options.ambiguity_offset_rad)}) {
    if (offset.isZero())
      continue;  // ambiguity_offset_rad 0: no turned starts
    const Pose2 start(solution.x() + offset.x(), solution.y() + offset.y(),
                      solution.theta() + offset.z());
    PlicpResult other = rematch(start, false, stop);
    if (other.converged())
      others.emplace_back(start, std::move(other));
  }
  // A clearly better fit (more of the new scan on reference surfaces) is the solution, also
  // when it finds the scene degenerate (the weak match was a wrong minimum, valid by chance).
  constexpr double kClearlyMoreInliers = 0.02;
  for (const auto& [start, other] : others) {
    if (!other.valid() && other.inlier_fraction > best.inlier_fraction + kClearlyMoreInliers)
      return rematch(start, true, nullptr);  // the same match, with its covariance
  }
  // Others as good, elsewhere (beyond 3 sigma): the data cannot tell them apart. A start that
  // finds the scene degenerate with as good a fit counts too: held along the weak direction
  // where it started, it fits there as well as the solution does.
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const auto& [start, other] : others) {
    if (other.inlier_fraction < best.inlier_fraction - kClearlyMoreInliers)
      continue;
    Eigen::Vector3d d = other.T_ref_new.vector() - best.T_ref_new.vector();
    d(2) = normalizeAngle(d(2));
    if (d.dot(best.covariance.ldlt().solve(d)) > 9.0)
      spread += d * d.transpose();
  }
  best.covariance += spread;
  return best;
}

}  // namespace odometry_calibration
