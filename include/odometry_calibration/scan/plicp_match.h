// One PLICP match from one initial guess, without the ambiguity check that matchScans adds
// (plicp.h): the iteration of correspondences, trimming and closed-form steps (Censi ICRA 2008),
// then the statistics, degeneracy and covariance at the solution.
#pragma once

#include <functional>
#include <memory>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/plicp.h"

namespace odometry_calibration {

/// Asked after each iteration of a match whether it may stop there: the iterate and the pose
/// uncertainty the next iteration's trimming would use (twice the last step's displacement of
/// the points) [m].
using IterationStop = std::function<bool(const Pose2& T_ref_new, double pose_uncertainty_m)>;

/// One match of `current` against `reference` from T_ref_new_guess (matchScans without the
/// ambiguity check; `options` already validated). Builds the search over the reference scan
/// into `search` unless an earlier match of the same scans did, so that the ambiguity check's
/// matches reuse it. When `stop` (if set) returns true after an iteration, the match ends there,
/// as kNoConvergence with a message saying so, `iterations` the iterations taken, and without
/// the statistics at the solution (the ambiguity check's rematches that are back at the
/// solution they check, plicp_ambiguity.h).
PlicpResult matchOnce(const PreparedScan& reference, const PreparedScan& current,
                      const Pose2& T_ref_new_guess, const PlicpOptions& options,
                      std::unique_ptr<NearestPointSearch>& search,
                      const IterationStop& stop = nullptr);

}  // namespace odometry_calibration
