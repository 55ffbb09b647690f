// The ambiguity check of weak PLICP matches (PlicpOptions::check_ambiguity, issue 16): the
// Censi covariance measures the noise of a match, not which of two equally good solutions is
// right. A weak or near-degenerate valid match is matched again from four starts around it;
// a clearly better fit replaces it, equally good fits elsewhere widen its covariance to cover
// them (docs/scan_matching.md, "Honest in weak scenes").
#pragma once

#include <functional>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/plicp.h"

namespace odometry_calibration {

/// Whether a match is weak enough to have its ambiguity checked: valid, with a covariance, and
/// either near degenerate (information ratio below ambiguity_max_information_ratio) or with
/// fewer than ambiguity_max_correspondences correspondences and a weakest translation sigma
/// above ambiguity_sigma_m or a heading sigma above ambiguity_sigma_rad.
bool needsAmbiguityCheck(const PlicpResult& result, const PlicpOptions& options);

/// One rematch of the check: a match from `start`, with the covariance only if `with_covariance`.
using PlicpRematch = std::function<PlicpResult(const Pose2& start, bool with_covariance)>;

/// Matches again from `best`'s solution moved by +-ambiguity_offset_m along its weakest
/// direction and turned by +-ambiguity_offset_rad. A start that finds the scene degenerate with
/// a clearly better fit (2 % more inliers) is returned instead (matched once more, with its
/// covariance); converged starts that fit as well (valid, or degenerate and held where they
/// started) but lie beyond 3 sigma add d d^T to the covariance (d: their offset). The rematches
/// skip their own covariance, which only a returned start needs (issue 33).
PlicpResult checkAmbiguity(PlicpResult best, const PlicpOptions& options,
                           const PlicpRematch& rematch);

}  // namespace odometry_calibration
