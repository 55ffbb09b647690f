// The PLICP ambiguity check's work counted in correspondence passes, for the covariance-cost rows
// of bench/plicp_covariance_cost.h. Header-only benchmark helper; not part of the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/plicp_match.h"

namespace odometry_calibration {
namespace ambiguity_passes {

/// The ambiguity check's work in correspondence passes (iterations, plus the pass at the solution
/// of a rematch that concludes), summed over the log's checked matches.
struct CheckPasses
{
  int checked = 0;
  int match = 0;                     // the matches themselves
  int rematches_now = 0;             // their rematches, with the early stop
  int rematches_before = 0;          // ... run to convergence
  int rematches_beyond_3_sigma = 0;  // ... of the rematches that end beyond 3 sigma, as good a fit
  int stopped = 0;                   // rematches the early stop ended
};

/// What the widening rematches (run to convergence, ending beyond 3 sigma of the match with as
/// good a fit) look like, for what would make the check cheaper: a cap on their passes, a looser
/// return bound, fewer starts, or a trigger on the match's covariance.
struct WideningEvidence
{
  int widened = 0;               // checked matches that at least one rematch widens
  int widened_by_one_start = 0;  // ... by exactly one of the four starts
  std::vector<int> passes;       // passes of each widening rematch
  int within_1_sigma = 0;        // widening rematches with an iterate within 1 sigma of the
  int within_1_5_sigma = 0;      // ... 1.5 sigma, after a step below the trimming floor
  std::vector<double> sigma_widened_m, sigma_kept_m;  // weakest translation sigma of the checked
                                                      // matches widened / not widened
};

/// The rematch of the check with every rematch run to convergence (`options`, no early stop)
/// that records into `evidence` what each widening rematch looked like on its way: the smallest
/// Mahalanobis distance to `best`'s solution among its iterates reached by a step below the
/// trimming floor (where the early stop may fire), and its passes. `widening_starts` counts the
/// starts that widen.
inline PlicpResult tracedRematch(const PreparedScan& reference, const PreparedScan& current,
                                 const PlicpResult& best, const PlicpOptions& options,
                                 std::unique_ptr<NearestPointSearch>& search, const Pose2& start,
                                 WideningEvidence& evidence, int& widening_starts)
{
  const Eigen::Matrix3d information = best.covariance.inverse();
  double closest_sigma = std::numeric_limits<double>::infinity();
  const IterationStop watch = [&](const Pose2& T_ref_new, double pose_uncertainty_m) {
    Eigen::Vector3d d = T_ref_new.vector() - best.T_ref_new.vector();
    d(2) = normalizeAngle(d(2));
    if (pose_uncertainty_m <= options.adaptive_trim_floor_m)
      closest_sigma = std::min(closest_sigma, std::sqrt(d.dot(information * d)));
    return false;  // watches only: the rematch runs as without it
  };
  PlicpOptions rematch_options = options;
  rematch_options.compute_covariance = false;
  PlicpResult other = matchOnce(reference, current, start, rematch_options, search, watch);
  Eigen::Vector3d d = other.T_ref_new.vector() - best.T_ref_new.vector();
  d(2) = normalizeAngle(d(2));
  if (other.converged() && other.inlier_fraction >= best.inlier_fraction - 0.02 &&
      d.dot(best.covariance.ldlt().solve(d)) > 9.0) {
    ++widening_starts;
    evidence.passes.push_back(other.iterations + 1);
    evidence.within_1_sigma += closest_sigma < 1.0 ? 1 : 0;
    evidence.within_1_5_sigma += closest_sigma < 1.5 ? 1 : 0;
  }
  return other;
}

/// Gathers the widening evidence of one checked match (`options`: rematches to convergence).
inline void gatherWideningEvidence(const PreparedScan& reference, const PreparedScan& current,
                                   const PlicpResult& best, const PlicpOptions& options,
                                   WideningEvidence& evidence)
{
  std::unique_ptr<NearestPointSearch> search;
  int widening_starts = 0;
  checkAmbiguity(best, options,
                 [&](const Pose2& start, bool with_covariance, const IterationStop&) {
                   if (with_covariance)  // the replacement of a clearly better fit: not a rematch
                     return matchOnce(reference, current, start, options, search);
                   return tracedRematch(reference, current, best, options, search, start, evidence,
                                        widening_starts);
                 });
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(best.covariance.topLeftCorner<2, 2>());
  const double sigma_m = std::sqrt(std::max(eigen.eigenvalues()(1), 0.0));
  (widening_starts > 0 ? evidence.sigma_widened_m : evidence.sigma_kept_m).push_back(sigma_m);
  evidence.widened += widening_starts > 0 ? 1 : 0;
  evidence.widened_by_one_start += widening_starts == 1 ? 1 : 0;
}

/// The passes of one checked match's rematches (checkAmbiguity with counting rematches) with
/// `options`; those of rematches that end converged beyond 3 sigma of `best` with as good a fit
/// (the ones that widen) into `beyond_3_sigma`.
inline int rematchPasses(const PreparedScan& reference, const PreparedScan& current,
                         const PlicpResult& best, const PlicpOptions& options, int& beyond_3_sigma,
                         int& stopped)
{
  std::unique_ptr<NearestPointSearch> search;
  int passes = 0;
  checkAmbiguity(
      best, options, [&](const Pose2& start, bool with_covariance, const IterationStop& stop) {
        PlicpOptions rematch_options = options;
        rematch_options.compute_covariance = with_covariance;
        PlicpResult other = matchOnce(reference, current, start, rematch_options, search, stop);
        const bool was_stopped = other.message.rfind("stopped", 0) == 0;
        stopped += was_stopped ? 1 : 0;
        const int own = other.iterations + (was_stopped ? 0 : 1);
        passes += own;
        Eigen::Vector3d d = other.T_ref_new.vector() - best.T_ref_new.vector();
        d(2) = normalizeAngle(d(2));
        if (other.converged() && other.inlier_fraction >= best.inlier_fraction - 0.02 &&
            d.dot(best.covariance.ldlt().solve(d)) > 9.0)
          beyond_3_sigma += own;
        return other;
      });
  return passes;
}

}  // namespace ambiguity_passes
}  // namespace odometry_calibration
