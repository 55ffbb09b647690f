// Covariance of a PLICP match and the degeneracy report derived from its information matrix.
//
// Covariance: A. Censi, "An accurate closed-form estimate of ICP's covariance", ICRA 2007. The
// estimate x = argmin J(x, z) moves with the readings z as dx = -(d2J/dx2)^-1 (d2J/dz dx) dz, so
//   cov(x) = (d2J/dx2)^-1 (d2J/dz dx) cov(z) (d2J/dz dx)^T (d2J/dx2)^-1.
// Here J = sum_i r_i^2 with r_i = n_j^T (R p_i + t - c_j), the first-order (Gauss-Newton) terms
// of both derivatives, and z = every range reading of both scans with cov(z) = sigma^2 I. A new
// point's range moves its own residual; a reference range moves the fitted line (its centroid
// and its direction) of every window it belongs to, hence the residuals of every new point
// matched to those lines. Because the lines are fitted over many neighbours, a featureless wall
// gives (almost) no information along itself, unlike the two-point normals of the paper.
//
// Degeneracy: the scaled information matrix H = sum_i J_i J_i^T (rotation expressed as the
// displacement it causes at the points' RMS radius) is eigen-decomposed; a direction whose
// information is below a fraction of the strongest one is reported as unconstrained.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/scan/scan_lines.h"

namespace odometry_calibration {

/// One point-to-line correspondence: point `current_index` of the new scan on the line of point
/// `reference_index` of the reference scan, with its signed residual [m].
struct Correspondence
{
  int current_index = -1;
  int reference_index = -1;
  double residual_m = 0.0;
};

/// Which motion the scene leaves unconstrained.
enum class DegenerateDirection
{
  kNone,         ///< everything constrained
  kTranslation,  ///< translation along `axis_ref` (e.g. a corridor's axis)
  kRotation,     ///< rotation (about `rotation_center_ref_m`, e.g. inside a round room)
  kSeveral,      ///< two or more directions: the scan does not determine the motion
};

/// Degeneracy report of a match.
struct Degeneracy
{
  DegenerateDirection direction = DegenerateDirection::kNone;
  /// Unit direction of the unconstrained translation, reference frame (kTranslation).
  Eigen::Vector2d axis_ref = Eigen::Vector2d::Zero();
  /// Centre of the unconstrained rotation, reference frame [m] (kRotation).
  Eigen::Vector2d rotation_center_ref_m = Eigen::Vector2d::Zero();
  /// Weakest over strongest eigenvalue of the scaled information matrix [-].
  double information_ratio = 1.0;
  /// Human-readable verdict naming the direction; empty when not degenerate.
  std::string description;

  bool degenerate() const { return direction != DegenerateDirection::kNone; }
};

/// Information matrix H = sum_i J_i J_i^T of the point-to-line residuals at T_ref_new, with
/// J_i = d r_i / d(t_x, t_y, theta) = (n, (R p_i) x n) [m^0, m^0, m]. Also returns the RMS
/// distance of the matched points from the new scan's origin (the lever arm of a rotation) [m].
Eigen::Matrix3d pointToLineInformation(const ScanPoints& reference,
                                       const ScanLines& reference_lines, const ScanPoints& current,
                                       const std::vector<Correspondence>& correspondences,
                                       const Pose2& T_ref_new, double* lever_arm_m);

/// Degeneracy of `information` (from pointToLineInformation): eigen-directions of
/// D^-1 H D^-1, D = diag(1, 1, lever_arm_m), whose eigenvalue is below
/// min_information_ratio times the largest one.
Degeneracy analyzeDegeneracy(const Eigen::Matrix3d& information, double lever_arm_m,
                             double min_information_ratio);

/// Censi ICRA 2007 covariance of (t_x [m], t_y [m], theta [rad]) of T_ref_new, for range noise
/// of standard deviation range_sigma_m [m] on every reading. Returns a matrix of +inf on the
/// diagonal when the information matrix is singular.
Eigen::Matrix3d plicpCovariance(const ScanPoints& reference, const ScanLines& reference_lines,
                                const ScanPoints& current,
                                const std::vector<Correspondence>& correspondences,
                                const Pose2& T_ref_new, double range_sigma_m);

}  // namespace odometry_calibration
