#include "odometry_calibration/scan/plicp.h"

#include <memory>

#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/plicp_match.h"
#include "odometry_calibration/scan/veiling_points.h"

namespace odometry_calibration {

const char* toString(PlicpStatus status)
{
  switch (status) {
    case PlicpStatus::kValid:
      return "valid";
    case PlicpStatus::kDegenerate:
      return "degenerate";
    case PlicpStatus::kTooFewPoints:
      return "too few points";
    case PlicpStatus::kTooFewCorrespondences:
      return "too few correspondences";
    case PlicpStatus::kNoConvergence:
      return "no convergence";
    case PlicpStatus::kCorrectionTooLarge:
      return "correction too large";
    case PlicpStatus::kPoorOverlap:
      return "poor overlap";
    case PlicpStatus::kUnconstrained:
      return "unconstrained";
  }
  return "unknown";
}

PreparedScan prepareScan(const Scan& scan, const LineFitOptions& options,
                         const SensorVelocity& velocity)
{
  validate(options);
  PreparedScan prepared;
  prepared.points = scanToPoints(scan, velocity);
  if (options.veiling_min_angle_rad > 0.0) {
    prepared.points = removePoints(prepared.points,
                                   findVeilingPoints(prepared.points, options.veiling_min_angle_rad,
                                                     options.veiling_max_ray_gap));
  }
  prepared.lines = fitScanLines(prepared.points, options);
  return prepared;
}

/// Whether a match may have failed for its gate's reach rather than the scene: too few new points
/// within max_correspondence_distance_m of a reference surface (at the guess, or where the
/// iteration led), or a run to a pose the checks refuse (off the allowed correction, or leaving
/// most of the scan off the reference surfaces): with the far points out of reach, the near ones
/// led it into a wrong minimum.
bool refusedForReach(const PlicpResult& result)
{
  switch (result.status) {
    case PlicpStatus::kTooFewCorrespondences:
    case PlicpStatus::kCorrectionTooLarge:
    case PlicpStatus::kPoorOverlap:
      return true;
    default:
      return false;
  }
}

PlicpResult matchScans(const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options)
{
  validate(options);
  std::unique_ptr<NearestPointSearch> search;  // built once, shared by the ambiguity check
  PlicpOptions gated = options;                // the gate the match ends with
  PlicpResult result = matchOnce(reference, current, T_ref_new_guess, gated, search);
  for (int doubling = 0;
       doubling < options.max_correspondence_distance_doublings && refusedForReach(result);
       ++doubling) {
    gated.max_correspondence_distance_m *= 2.0;
    result = matchOnce(reference, current, T_ref_new_guess, gated, search);
  }
  if (needsAmbiguityCheck(result, gated)) {
    result =
        checkAmbiguity(std::move(result), gated,
                       [&](const Pose2& start, bool with_covariance, const IterationStop& stop) {
                         PlicpOptions rematch_options = gated;
                         rematch_options.compute_covariance = with_covariance;
                         return matchOnce(reference, current, start, rematch_options, search, stop);
                       });
  }
  return result;
}

PlicpResult matchScans(const Scan& reference, const Scan& current, const Pose2& T_ref_new_guess,
                       const PlicpOptions& options)
{
  validate(options);
  return matchScans(prepareScan(reference, options.line_fit),
                    prepareScan(current, options.line_fit), T_ref_new_guess, options);
}

}  // namespace odometry_calibration
