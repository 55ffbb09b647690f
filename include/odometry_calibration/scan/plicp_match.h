// One PLICP match from one initial guess, without the ambiguity check that matchScans adds
// (plicp.h): the iteration of correspondences, trimming and closed-form steps (Censi ICRA 2008),
// then the statistics, degeneracy and covariance at the solution.
#pragma once

#include <memory>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/plicp.h"

namespace odometry_calibration {

/// One match of `current` against `reference` from T_ref_new_guess (matchScans without the
/// ambiguity check; `options` already validated). Builds the search over the reference scan
/// into `search` unless an earlier match of the same scans did, so that the ambiguity check's
/// matches reuse it.
PlicpResult matchOnce(const PreparedScan& reference, const PreparedScan& current,
                      const Pose2& T_ref_new_guess, const PlicpOptions& options,
                      std::unique_ptr<NearestPointSearch>& search);

}  // namespace odometry_calibration
