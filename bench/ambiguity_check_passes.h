// The PLICP ambiguity check's work counted in correspondence passes, for the covariance-cost rows
// of bench/plicp_vs_csm_bench.cpp (issue 33). Header-only benchmark helper; not part of the
// library.
#pragma once

#include <memory>

#include <Eigen/Cholesky>

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
