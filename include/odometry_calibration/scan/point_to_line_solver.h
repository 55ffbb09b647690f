// The closed-form step of PLICP: the rigid motion that minimises the sum of squared point-to-line
// distances of a fixed set of correspondences (A. Censi, "An ICP variant using a point-to-line
// metric", ICRA 2008, Sec. IV and its appendix).
//
// With x = (t_x, t_y, cos(theta), sin(theta)) every residual n_i^T (R(theta) p_i + t - c_i) is
// linear in x, so the cost is the quadratic form x^T A x - 2 g^T x + const under the constraint
// x_3^2 + x_4^2 = 1. Censi solves it with a Lagrange multiplier lambda: (A + lambda W) x = g with
// W = diag(0, 0, 1, 1), whose solvability condition is a fourth-order polynomial in lambda; the
// minimum is at its largest real root. Here the translation is eliminated first (Schur
// complement), which leaves (S + lambda I) r = h for r = (cos, sin) and the equivalent secular
// equation |(S + lambda I)^-1 h| = 1. In the eigenbasis of the 2x2 S its left side decreases
// monotonically above -s_min, so the root is bracketed and found to machine precision
// (safeguarded Newton), without the round-off of a general quartic solver.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// Components of the motion the step must keep at given values: used when the scene does not
/// constrain them (a corridor's axis, a round room's rotation), so that noise cannot move them.
struct StepConstraint
{
  /// Hold the translation's component along `fixed_axis_ref` (unit, reference frame) at
  /// `fixed_along_m` [m].
  bool fix_translation_along_axis = false;
  Eigen::Vector2d fixed_axis_ref = Eigen::Vector2d::UnitX();
  double fixed_along_m = 0.0;
  /// Hold the rotation at `fixed_theta_rad` [rad].
  bool fix_rotation = false;
  double fixed_theta_rad = 0.0;
};

/// Accumulates point-to-line correspondences and solves for the motion in closed form.
///
/// A correspondence pairs a point p of the new scan (new frame) with a line of the reference scan
/// (a point c on it and its unit normal n, reference frame); its residual under T_ref_new is
/// n^T (T_ref_new * p - c) [m]. The system keeps only the 4x4 normal equations, so adding is
/// O(1) and solving O(1).
class PointToLineSystem
{
public:
  /// Adds the residual w * (n^T (R p + t - c))^2 to the cost. `weight` >= 0 [-].
  void add(const Eigen::Vector2d& point_new_m, const Eigen::Vector2d& line_point_ref_m,
           const Eigen::Vector2d& line_normal_ref, double weight = 1.0);

  /// Number of correspondences added.
  int count() const { return count_; }

  /// Gauss-Newton information matrix sum_i J_i J_i^T of the accumulated residuals in
  /// (t_x [m], t_y [m], theta [rad]) at rotation theta_rad, as pointToLineInformation()
  /// (plicp_covariance.h) computes it, in O(1): the residual's gradient is J = B m with m the
  /// row of the normal equations and B = [1 0 0 0; 0 1 0 0; 0 0 -sin(theta) cos(theta)], so the
  /// information is B A B^T.
  Eigen::Matrix3d information(double theta_rad) const;

  /// The minimiser T_ref_new of the accumulated cost under `constraint` (Censi ICRA 2008,
  /// closed form above), or nullopt when the correspondences do not determine it (fewer than
  /// two independent line directions for the free translation, or no information on rotation).
  std::optional<Pose2> solve(const StepConstraint& constraint = {}) const;

private:
  Eigen::Matrix4d normal_matrix_ = Eigen::Matrix4d::Zero();  // A (upper triangle)
  Eigen::Vector4d normal_vector_ = Eigen::Vector4d::Zero();  // g
  int count_ = 0;
};

/// Minimiser of r^T S r - 2 h^T r over unit vectors r (the rotation part of the step above):
/// the Lagrange condition (S + lambda I) r = h at the largest admissible root lambda of the
/// secular equation. Returns nullopt when every unit vector is a minimiser (S isotropic, h = 0).
std::optional<Eigen::Vector2d> minimizeQuadraticOnUnitCircle(const Eigen::Matrix2d& S,
                                                             const Eigen::Vector2d& h);

}  // namespace odometry_calibration
