// Point-to-line ICP between two planar scans, with covariance and a degeneracy report.
//
// Method: A. Censi, "An ICP variant using a point-to-line metric", ICRA 2008 (PLICP): every
// iteration matches each point of the new scan to the reference surface nearest to it, trims
// outliers (a fixed percentile and an adaptive threshold) and solves for the motion in closed
// form (point_to_line_solver.h). The reference surface of a point is a line fitted over its
// neighbours (scan_lines.h) instead of the segment to its nearest neighbour, so the normals and
// with them the covariance of A. Censi, "An accurate closed-form estimate of ICP's covariance",
// ICRA 2007 (plicp_covariance.h) reflect the scene rather than the range noise.
//
// Frames: the result T_ref_new is the pose of the new scan's sensor frame in the reference
// scan's sensor frame (it maps new-scan points into the reference frame), i.e. the sensor's
// motion from the reference scan to the new one.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/plicp_covariance.h"
#include "odometry_calibration/scan/plicp_options.h"
#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/scan/scan_lines.h"

namespace odometry_calibration {

/// A scan turned into points with their local lines, ready to be matched (once per scan; a scan
/// can serve as new scan of one match and reference of the next).
struct PreparedScan
{
  ScanPoints points;
  ScanLines lines;
};

/// Converts the usable readings (scanToPoints, compensating the motion during the sweep when
/// `velocity` is given and the scan has a time_increment_s) and fits their lines (fitScanLines).
/// Throws std::invalid_argument for an unusable scan geometry or invalid line-fit options.
PreparedScan prepareScan(const Scan& scan, const LineFitOptions& options,
                         const SensorVelocity& velocity = {});

/// Outcome of a match.
enum class PlicpStatus
{
  kValid,                  ///< converged; x, y and heading all measured
  kDegenerate,             ///< converged, but one direction is not constrained (see degeneracy)
  kTooFewPoints,           ///< a scan has fewer usable points (reference: lines) than min_points
  kTooFewCorrespondences,  ///< an iteration kept fewer than min_correspondences
  kNoConvergence,          ///< max_iterations reached without meeting the tolerances
  kCorrectionTooLarge,     ///< the pose left the allowed correction around the initial guess
  kPoorOverlap,            ///< converged, but too few points lie on reference surfaces
  kUnconstrained,          ///< the scene constrains fewer than two directions of motion
};

/// Short name of a status ("valid", "degenerate", "too few points", ...).
const char* toString(PlicpStatus status);

/// Result of matchScans().
struct PlicpResult
{
  PlicpStatus status = PlicpStatus::kTooFewPoints;
  /// Why the match failed or is degenerate, in words; empty when valid.
  std::string message;
  /// Pose of the new scan in the reference scan's frame [m, m, rad]. On failure the last
  /// iterate (or the initial guess); along a degenerate direction, the initial guess.
  Pose2 T_ref_new;
  /// Covariance of (x [m], y [m], theta [rad]) of T_ref_new (Censi ICRA 2007, with the line-fit
  /// normals) [m^2, m^2 rad, rad^2]. Along a degenerate direction it is large (nothing measured
  /// there). Zero when not computed (failure or compute_covariance = false).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  int iterations = 0;            ///< closed-form steps taken
  int correspondence_count = 0;  ///< correspondences kept after trimming, at the solution
  double mean_residual_m = 0.0;  ///< mean |point-to-line residual| of those [m]
  /// New scan's points with a line of their own within inlier_distance_m of a reference line,
  /// over all its points with a line [-].
  double inlier_fraction = 0.0;
  Degeneracy degeneracy;  ///< which direction, if any, the scene leaves unconstrained

  /// Converged (valid or degenerate): the constrained components are measurements.
  bool converged() const
  {
    return status == PlicpStatus::kValid || status == PlicpStatus::kDegenerate;
  }
  /// A full measurement of x, y and heading.
  bool valid() const { return status == PlicpStatus::kValid; }
};

/// Whether a match may have failed for its gate's reach rather than the scene (too few
/// correspondences, correction too large, poor overlap): matchScans matches those again with
/// max_correspondence_distance_m doubled, up to max_correspondence_distance_doublings times.
bool refusedForReach(const PlicpResult& result);

/// Matches `current` against `reference` starting from `T_ref_new_guess` (e.g. from odometry).
/// Never throws for bad data (too few points, no convergence, ... are statuses); throws
/// std::invalid_argument only for invalid options.
PlicpResult matchScans(const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options);

/// Convenience: prepares both scans, then matches them. Throws std::invalid_argument for invalid
/// options or an unusable scan geometry.
PlicpResult matchScans(const Scan& reference, const Scan& current, const Pose2& T_ref_new_guess,
                       const PlicpOptions& options);

}  // namespace odometry_calibration
