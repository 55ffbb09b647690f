#include "odometry_calibration/scan/point_to_line_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace odometry_calibration {
namespace {

// Relative size below which a pivot counts as zero: the data do not determine that component.
constexpr double kSingularRelative = 1e-12;

/// Solves the secular equation phi(l) = sum_k h_k^2 / (s_k + l)^2 - 1 = 0 for its root above
/// -s_min, where phi falls monotonically from >= 0 to -1. `s` ascending, `h` in the eigenbasis.
double largestSecularRoot(const Eigen::Vector2d& s, const Eigen::Vector2d& h)
{
  // Bracket: at l = -s_min + |h_min| the first term alone is 1 (phi >= 0); at l = -s_min + |h|
  // every term is at most h_k^2 / |h|^2 (phi <= 0).
  double low = -s(0) + std::abs(h(0));
  double high = -s(0) + h.norm();
  // Newton on psi(l) = 1 - 1/|r(l)|, almost linear in l (More & Sorensen's trust-region trick),
  // falling back to bisection whenever a step leaves the bracket.
  double lambda = high;
  for (int iteration = 0; iteration < 100 && high - low > 0.0; ++iteration) {
    const Eigen::Vector2d shifted(s(0) + lambda, s(1) + lambda);
    const Eigen::Vector2d r(h(0) / shifted(0), h(1) / shifted(1));
    const double norm = r.norm();
    const double psi = 1.0 - 1.0 / norm;
    if (psi > 0.0) {
      low = lambda;  // |r| > 1: the root lies above
    } else {
      high = lambda;
    }
    if (psi == 0.0) {
      break;
    }
    // d|r|/dl = -sum r_k^2 / (s_k + l) / |r|, so dpsi/dl = (d|r|/dl) / |r|^2.
    const double dnorm = -(r(0) * r(0) / shifted(0) + r(1) * r(1) / shifted(1)) / norm;
    const double slope = dnorm / (norm * norm);
    double next = slope != 0.0 ? lambda - psi / slope : 0.5 * (low + high);
    if (!(next > low && next < high)) {
      next = 0.5 * (low + high);
    }
    if (next == lambda) {
      break;
    }
    lambda = next;
  }
  return lambda;
}

}  // namespace

std::optional<Eigen::Vector2d> minimizeQuadraticOnUnitCircle(const Eigen::Matrix2d& S,
                                                             const Eigen::Vector2d& h)
{
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
  eigen.computeDirect(S);
  const Eigen::Vector2d s = eigen.eigenvalues();  // ascending
  const Eigen::Matrix2d V = eigen.eigenvectors();
  const Eigen::Vector2d h_eigen = V.transpose() * h;
  const double scale = std::max({std::abs(s(0)), std::abs(s(1)), h.norm()});
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    return std::nullopt;
  }
  const double tiny = kSingularRelative * scale;
  Eigen::Vector2d r_eigen;
  if (std::abs(h_eigen(0)) <= tiny) {
    // "Hard case" of the trust-region subproblem: the Lagrange multiplier may sit at -s_min.
    const double gap = s(1) - s(0);
    const double r1 = gap > tiny ? h_eigen(1) / gap : (std::abs(h_eigen(1)) <= tiny ? 0.0 : 2.0);
    if (std::abs(r1) <= 1.0) {
      if (gap <= tiny && std::abs(h_eigen(1)) <= tiny) {
        return std::nullopt;  // S isotropic and h = 0: every rotation costs the same
      }
      r_eigen = Eigen::Vector2d(std::sqrt(std::max(0.0, 1.0 - r1 * r1)), r1);
      return V * r_eigen;
    }
  }
  const double lambda = largestSecularRoot(s, h_eigen);
  r_eigen = Eigen::Vector2d(h_eigen(0) / (s(0) + lambda), h_eigen(1) / (s(1) + lambda));
  const double norm = r_eigen.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    return std::nullopt;
  }
  return V * (r_eigen / norm);
}

void PointToLineSystem::add(const Eigen::Vector2d& point_new_m,
                            const Eigen::Vector2d& line_point_ref_m,
                            const Eigen::Vector2d& line_normal_ref, double weight)
{
  // Residual m^T x - b with x = (tx, ty, cos, sin): n^T R p = cos (n.p) + sin (n x p).
  const Eigen::Vector2d& n = line_normal_ref;
  const Eigen::Vector2d& p = point_new_m;
  const double m0 = n.x();
  const double m1 = n.y();
  const double m2 = n.dot(p);
  const double m3 = n.y() * p.x() - n.x() * p.y();
  const double b = n.dot(line_point_ref_m);
  // Upper triangle of A += w m m^T and g += w b m, written out (this runs for every
  // correspondence of every iteration).
  double* a = normal_matrix_.data();  // column-major: (row, column) at row + 4 column
  const double w0 = weight * m0;
  const double w1 = weight * m1;
  const double w2 = weight * m2;
  const double w3 = weight * m3;
  a[0] += w0 * m0;
  a[4] += w0 * m1;
  a[5] += w1 * m1;
  a[8] += w0 * m2;
  a[9] += w1 * m2;
  a[10] += w2 * m2;
  a[12] += w0 * m3;
  a[13] += w1 * m3;
  a[14] += w2 * m3;
  a[15] += w3 * m3;
  normal_vector_(0) += w0 * b;
  normal_vector_(1) += w1 * b;
  normal_vector_(2) += w2 * b;
  normal_vector_(3) += w3 * b;
  ++count_;
}

Eigen::Matrix3d PointToLineSystem::information(double theta_rad) const
{
  const Eigen::Matrix4d A = normal_matrix_.selfadjointView<Eigen::Upper>();
  Eigen::Matrix<double, 3, 4> B = Eigen::Matrix<double, 3, 4>::Zero();
  B(0, 0) = 1.0;
  B(1, 1) = 1.0;
  B(2, 2) = -std::sin(theta_rad);
  B(2, 3) = std::cos(theta_rad);
  return B * A * B.transpose();
}

std::optional<Pose2> PointToLineSystem::solve(const StepConstraint& constraint) const
{
  Eigen::Matrix4d A = normal_matrix_.selfadjointView<Eigen::Upper>();
  const Eigen::Vector4d& g = normal_vector_;
  const double scale = A.diagonal().cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    return std::nullopt;
  }

  // Free translation t = t0 + P u: all of it, or only the part across a held axis.
  Eigen::Vector2d t0 = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, 2> P;
  if (constraint.fix_translation_along_axis) {
    const Eigen::Vector2d axis = constraint.fixed_axis_ref.normalized();
    t0 = constraint.fixed_along_m * axis;
    P.resize(2, 1);
    P.col(0) = Eigen::Vector2d(-axis.y(), axis.x());
  } else {
    P = Eigen::Matrix2d::Identity();
  }
  // Cost in (u, r): A_uu = P^T A_tt P, A_ur = P^T A_tr, gradient terms shifted by t0.
  const Eigen::Matrix2d A_tt = A.topLeftCorner<2, 2>();
  const Eigen::Matrix2d A_tr = A.topRightCorner<2, 2>();
  const Eigen::Matrix2d A_rr = A.bottomRightCorner<2, 2>();
  const Eigen::MatrixXd A_uu = P.transpose() * A_tt * P;
  const Eigen::MatrixXd A_ur = P.transpose() * A_tr;
  const Eigen::VectorXd g_u = P.transpose() * (g.head<2>() - A_tt * t0);
  const Eigen::Vector2d g_r = g.tail<2>() - A_tr.transpose() * t0;

  Eigen::LDLT<Eigen::MatrixXd> A_uu_ldlt(A_uu);
  const Eigen::VectorXd pivots = A_uu_ldlt.vectorD();
  if (A_uu_ldlt.info() != Eigen::Success || pivots.minCoeff() <= kSingularRelative * scale) {
    return std::nullopt;  // the lines do not pin the free translation down
  }

  Eigen::Vector2d r;
  if (constraint.fix_rotation) {
    r = Eigen::Vector2d(std::cos(constraint.fixed_theta_rad), std::sin(constraint.fixed_theta_rad));
  } else {
    // Eliminate the translation: u*(r) = A_uu^-1 (g_u - A_ur r).
    const Eigen::MatrixXd A_uu_inv_A_ur = A_uu_ldlt.solve(A_ur);
    const Eigen::VectorXd A_uu_inv_g_u = A_uu_ldlt.solve(g_u);
    const Eigen::Matrix2d S = A_rr - A_ur.transpose() * A_uu_inv_A_ur;
    const Eigen::Vector2d h = g_r - A_ur.transpose() * A_uu_inv_g_u;
    const std::optional<Eigen::Vector2d> rotation = minimizeQuadraticOnUnitCircle(S, h);
    if (!rotation) {
      return std::nullopt;
    }
    r = *rotation;
  }
  const Eigen::VectorXd u = A_uu_ldlt.solve(g_u - A_ur * r);
  const Eigen::Vector2d t = t0 + P * u;
  const double theta_rad = constraint.fix_rotation ? normalizeAngle(constraint.fixed_theta_rad)
                                                   : std::atan2(r.y(), r.x());
  return Pose2(t.x(), t.y(), theta_rad);
}

}  // namespace odometry_calibration
