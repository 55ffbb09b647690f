#include "odometry_calibration/scan/plicp_covariance.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace odometry_calibration {
namespace {

/// 2D cross product a x b.
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() * b.y() - a.y() * b.x();
}

/// d r / d(t_x, t_y, theta) of r = n^T (R p + t - c), with Rp = R p already rotated:
/// dR/dtheta p = perp(R p) = (-(Rp)_y, (Rp)_x), so dr/dtheta = n^T perp(R p) = (R p) x n.
Eigen::Vector3d residualJacobian(const Eigen::Vector2d& normal, const Eigen::Vector2d& Rp)
{
  return Eigen::Vector3d(normal.x(), normal.y(), cross(Rp, normal));
}

/// Upper triangle of m += w v v^T, written out (Eigen's rankUpdate is not inlined here and this
/// runs for every correspondence).
void addOuterProduct(Eigen::Matrix3d& m, const Eigen::Vector3d& v, double w = 1.0)
{
  const double w0 = w * v(0);
  const double w1 = w * v(1);
  const double w2 = w * v(2);
  m(0, 0) += w0 * v(0);
  m(0, 1) += w0 * v(1);
  m(0, 2) += w0 * v(2);
  m(1, 1) += w1 * v(1);
  m(1, 2) += w1 * v(2);
  m(2, 2) += w2 * v(2);
}

using Vector3dList = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;

/// Per-reference-point sums of plicpCovariance(), kept per thread between calls (as long as the
/// reference scan; allocating and freeing them per match costs page faults on large scans).
struct CovarianceBuffers
{
  Vector3dList line_sum;
  Vector3dList line_moment;
  std::vector<std::uint8_t> line_used;
  Vector3dList reading_effect;
};

CovarianceBuffers& threadBuffers()
{
  thread_local CovarianceBuffers buffers;
  return buffers;
}

std::string formatVector(const Eigen::Vector2d& v, const char* unit)
{
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "(%.3f, %.3f)%s", v.x(), v.y(), unit);
  return buffer;
}

}  // namespace

Eigen::Matrix3d pointToLineInformation(const ScanPoints& /*reference*/,
                                       const ScanLines& reference_lines, const ScanPoints& current,
                                       const std::vector<Correspondence>& correspondences,
                                       const Pose2& T_ref_new, double* lever_arm_m)
{
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(T_ref_new.theta()).toRotationMatrix();
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  double radius2_sum_m2 = 0.0;
  for (const Correspondence& c : correspondences) {
    const Eigen::Vector2d Rp = R * current.points_m[c.current_index];
    const Eigen::Vector3d J = residualJacobian(reference_lines.normals[c.reference_index], Rp);
    addOuterProduct(information, J);
    radius2_sum_m2 += Rp.squaredNorm();
  }
  if (lever_arm_m != nullptr) {
    *lever_arm_m = correspondences.empty()
                       ? 1.0
                       : std::sqrt(radius2_sum_m2 / static_cast<double>(correspondences.size()));
  }
  return information.selfadjointView<Eigen::Upper>();
}

Degeneracy analyzeDegeneracy(const Eigen::Matrix3d& information, double lever_arm_m,
                             double min_information_ratio)
{
  Degeneracy report;
  const double lever_m = lever_arm_m > 0.0 ? lever_arm_m : 1.0;
  const Eigen::Vector3d scale(1.0, 1.0, 1.0 / lever_m);
  const Eigen::Matrix3d scaled = scale.asDiagonal() * information * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(scaled);
  const Eigen::Vector3d values = eigen.eigenvalues();  // ascending
  const double strongest = values(2);
  if (!(strongest > 0.0) || !std::isfinite(strongest)) {
    report.direction = DegenerateDirection::kSeveral;
    report.information_ratio = 0.0;
    report.description = "no information at all: no point-to-line correspondence";
    return report;
  }
  report.information_ratio = std::max(0.0, values(0)) / strongest;
  const double threshold = min_information_ratio * strongest;
  if (values(1) < threshold) {
    report.direction = DegenerateDirection::kSeveral;
    report.description = "the scene constrains only one direction of motion (information ratios " +
                         std::to_string(std::max(0.0, values(0)) / strongest) + ", " +
                         std::to_string(values(1) / strongest) +
                         "): the match does not determine the motion";
    return report;
  }
  if (values(0) >= threshold) {
    return report;
  }
  // Weakest direction in unscaled units: (dt_x, dt_y, dtheta).
  const Eigen::Vector3d weakest = scale.asDiagonal() * eigen.eigenvectors().col(0);
  const Eigen::Vector2d translation = weakest.head<2>();
  const double rotation_displacement_m = std::abs(weakest(2)) * lever_m;
  char ratio[64];
  std::snprintf(ratio, sizeof(ratio), "%.2g < %.2g", report.information_ratio,
                min_information_ratio);
  if (translation.norm() >= rotation_displacement_m) {
    report.direction = DegenerateDirection::kTranslation;
    report.axis_ref = translation.normalized();
    if (report.axis_ref.x() < 0.0 || (report.axis_ref.x() == 0.0 && report.axis_ref.y() < 0.0)) {
      report.axis_ref = -report.axis_ref;  // a canonical sign for the axis
    }
    report.description = "translation along " + formatVector(report.axis_ref, "") +
                         " in the reference scan frame is not constrained by the scene (e.g. a "
                         "featureless corridor; information ratio " +
                         ratio + "): that component is kept at the initial guess, not measured";
  } else {
    report.direction = DegenerateDirection::kRotation;
    // A small rotation dtheta about c moves the origin by dt = -dtheta perp(c), so
    // c = perp(dt) / dtheta with perp(v) = (-v_y, v_x).
    report.rotation_center_ref_m = Eigen::Vector2d(-translation.y(), translation.x()) / weakest(2);
    report.description = "rotation about " + formatVector(report.rotation_center_ref_m, " m") +
                         " in the reference scan frame is not constrained by the scene (e.g. a "
                         "round room; information ratio " +
                         ratio + "): the heading is kept at the initial guess, not measured";
  }
  return report;
}

namespace {

/// The two sides of the sandwich: information = d2J/dx2 / 2, spread = (d2J/dzdx)(d2J/dzdx)^T / 4
/// (upper triangles).
struct CovarianceSums
{
  Eigen::Matrix3d information;
  Eigen::Matrix3d spread;
};

/// The correspondences' information and their new points' range effects on the spread; sums
/// per reference line J_i and s_i J_i over the new points matched to it, s_i the matched
/// point's along-line offset from the line's centroid.
CovarianceSums sumCorrespondences(const ScanLines& reference_lines, const ScanPoints& current,
                                  const std::vector<Correspondence>& correspondences,
                                  const Pose2& T_ref_new, CovarianceBuffers& buffers)
{
  // Locals, not the caller's: the compiler keeps them apart from the buffers' memory.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(T_ref_new.theta()).toRotationMatrix();
  const Eigen::Vector2d t(T_ref_new.x(), T_ref_new.y());
  for (const Correspondence& c : correspondences) {
    const int j = c.reference_index;
    const Eigen::Vector2d& normal = reference_lines.normals[j];
    const Eigen::Vector2d Rp = R * current.points_m[c.current_index];
    const Eigen::Vector3d J = residualJacobian(normal, Rp);
    addOuterProduct(information, J);
    // The new point's own range moves its residual by n^T R u per metre.
    const double d_residual_d_range = normal.dot(R * current.directions[c.current_index]);
    addOuterProduct(spread, J, d_residual_d_range * d_residual_d_range);
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    const double along_m = tangent.dot(Rp + t - reference_lines.centroids_m[j]);
    buffers.line_sum[j] += J;
    buffers.line_moment[j] += along_m * J;
    buffers.line_used[j] = 1;
  }
  return {information, spread};
}

/// `spread` with the reference ranges' effects added. A reference range moves the perpendicular
/// offset d_k of its point by n^T u_k per metre; the total-least-squares line through the window
/// moves by dd_k / K at the centroid and tilts by s_k dd_k / sum(s^2), so a residual at
/// along-offset s changes by -(1/K + s s_k / sum(s^2)) dd_k.
Eigen::Matrix3d addReferenceReadings(const ScanPoints& reference, const ScanLines& reference_lines,
                                     CovarianceBuffers& buffers, Eigen::Matrix3d spread)
{
  const std::size_t reference_count = reference.size();
  Vector3dList& reading_effect = buffers.reading_effect;
  reading_effect.assign(reference_count, Eigen::Vector3d::Zero());
  for (std::size_t j = 0; j < reference_count; ++j) {
    if (buffers.line_used[j] == 0) {
      continue;
    }
    const Eigen::Vector2d& normal = reference_lines.normals[j];
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    const Eigen::Vector2d& centroid = reference_lines.centroids_m[j];
    const int first = reference_lines.first[j];
    const int last = reference_lines.last[j];
    const double inverse_count = 1.0 / static_cast<double>(last - first + 1);
    const double inverse_spread =
        reference_lines.spread_m2[j] > 0.0 ? 1.0 / reference_lines.spread_m2[j] : 0.0;
    // Copies: the stores into reading_effect could otherwise be the sums' memory.
    const Eigen::Vector3d line_sum = buffers.line_sum[j];
    const Eigen::Vector3d line_moment = buffers.line_moment[j];
    for (int k = first; k <= last; ++k) {
      const double offset_per_range = normal.dot(reference.directions[k]);
      const double along_k_m = tangent.dot(reference.points_m[k] - centroid);
      reading_effect[k] -= offset_per_range *
                           (inverse_count * line_sum + (along_k_m * inverse_spread) * line_moment);
    }
  }
  for (std::size_t k = 0; k < reference_count; ++k) {
    addOuterProduct(spread, reading_effect[k]);
  }
  return spread;
}

}  // namespace

Eigen::Matrix3d plicpCovariance(const ScanPoints& reference, const ScanLines& reference_lines,
                                const ScanPoints& current,
                                const std::vector<Correspondence>& correspondences,
                                const Pose2& T_ref_new, double range_sigma_m)
{
  const std::size_t reference_count = reference.size();
  CovarianceBuffers& buffers = threadBuffers();
  buffers.line_sum.assign(reference_count, Eigen::Vector3d::Zero());
  buffers.line_moment.assign(reference_count, Eigen::Vector3d::Zero());
  buffers.line_used.assign(reference_count, 0);
  const CovarianceSums sums =
      sumCorrespondences(reference_lines, current, correspondences, T_ref_new, buffers);
  const Eigen::Matrix3d& information = sums.information;
  const Eigen::Matrix3d spread =
      addReferenceReadings(reference, reference_lines, buffers, sums.spread);

  const Eigen::Matrix3d H = information.selfadjointView<Eigen::Upper>();
  const Eigen::Matrix3d G = spread.selfadjointView<Eigen::Upper>();
  Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()).asDiagonal();
  }
  const Eigen::Matrix3d H_inverse = ldlt.solve(Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d covariance = range_sigma_m * range_sigma_m * H_inverse * G * H_inverse;
  return 0.5 * (covariance + covariance.transpose());
}

}  // namespace odometry_calibration
