// The ambiguity check of weak PLICP matches (PlicpOptions::check_ambiguity): the
// Censi covariance measures the noise of a match, not which of two equally good solutions is
// right. A weak or near-degenerate valid match is matched again from four starts around it;
// a clearly better fit replaces it, equally good fits elsewhere widen its covariance to cover
// them (docs/scan_matching.md, "Honest in weak scenes").
#pragma once

#include <functional>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/plicp_match.h"

namespace odometry_calibration {

/// Whether a match is weak enough to have its ambiguity checked: valid, with a covariance, and
/// either near degenerate (information ratio below ambiguity_max_information_ratio) or with
/// fewer than ambiguity_max_correspondences correspondences and a weakest translation sigma
/// above ambiguity_sigma_m or a heading sigma above ambiguity_sigma_rad.
bool needsAmbiguityCheck(const PlicpResult& result, const PlicpOptions& options);

/// One rematch of the check: a match from `start`, with the covariance only if `with_covariance`,
/// that ends early (as kNoConvergence) once `stop` (if set) says so (matchOnce, plicp_match.h).
using PlicpRematch =
    std::function<PlicpResult(const Pose2& start, bool with_covariance, const IterationStop& stop)>;

/// The early stop of a rematch that is back at `best`'s solution: an iterate within
/// ambiguity_return_sigma of it (Mahalanobis distance under best.covariance), reached by a step
/// small enough that the next trimming keeps what it keeps near a converged solution (pose
/// uncertainty within adaptive_trim_floor_m: the threshold then depends on the pose alone). From
/// there the iteration is the one that converged to the solution, so the rematch would end
/// within 3 sigma of it with the same fit, changing nothing. Not a proof (the iteration map
/// jumps where the correspondences change: rematches seen passing within 0.1 sigma after a
/// large step, or within 1.5 sigma after a small one, end beyond 3 sigma); measured: on the
/// ACES and FHW logs and the tests' scenes no stopped rematch would have changed a match.
/// Null (no stop) when ambiguity_return_sigma is 0.
IterationStop backAtSolution(const PlicpResult& best, const PlicpOptions& options);

/// Matches again from `best`'s solution moved by +-ambiguity_offset_m along its weakest
/// direction and turned by +-ambiguity_offset_rad (no turned starts when it is 0). A start that
/// finds the scene degenerate with a clearly better fit (2 % more inliers) is returned instead
/// (matched once more, with its covariance); converged starts that fit as well (valid, or
/// degenerate and held where they started) but lie beyond 3 sigma add d d^T to the covariance (d:
/// their offset). The rematches skip their own covariance, which only a returned start needs, and
/// stop once back at the solution (backAtSolution).
PlicpResult checkAmbiguity(PlicpResult best, const PlicpOptions& options,
                           const PlicpRematch& rematch);

}  // namespace odometry_calibration
