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

PlicpResult matchScans(const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options)
{
  validate(options);
  std::unique_ptr<NearestPointSearch> search;  // built once, shared by the ambiguity check
  PlicpResult result = matchOnce(reference, current, T_ref_new_guess, options, search);
  if (needsAmbiguityCheck(result, options)) {
    result =
        checkAmbiguity(std::move(result), options,
                       [&](const Pose2& start, bool with_covariance, const IterationStop& stop) {
                         PlicpOptions rematch_options = options;
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
