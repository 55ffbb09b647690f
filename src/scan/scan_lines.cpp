#include "odometry_calibration/scan/scan_lines.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odometry_calibration {
namespace {

void require(bool condition, const std::string& message)
{
  if (!condition) {
    throw std::invalid_argument(message);
  }
}

/// A total-least-squares line through a window of points.
struct WindowFit
{
  int first = 0;
  int last = -1;
  int count = 0;
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  Eigen::Vector2d centroid_m = Eigen::Vector2d::Zero();
  double across_m2 = 0.0;  // sum of squared distances to the line
  double along_m2 = 0.0;   // sum of squared along-line offsets from the centroid

  /// Mean squared distance to the line, per degree of freedom [m^2].
  double meanSquare() const { return count > 2 ? across_m2 / (count - 2) : 0.0; }
};

/// Running sums of 1, x, y, xx, xy, yy over points [0, i), in coordinates relative to the first
/// point of each point's surface (keeps the sums small: no cancellation far from the sensor).
struct PrefixMoments
{
  std::vector<double> x, y, xx, xy, yy;

  explicit PrefixMoments(std::size_t n) : x(n + 1), y(n + 1), xx(n + 1), xy(n + 1), yy(n + 1) {}
};

}  // namespace

void validate(const LineFitOptions& options, const std::string& prefix)
{
  require(std::isfinite(options.radius_m) && options.radius_m > 0.0,
          prefix + "radius_m must be a positive number of metres");
  require(options.max_neighbors_per_side >= 1,
          prefix + "max_neighbors_per_side must be at least 1");
  require(options.min_points >= 3, prefix + "min_points must be at least 3");
  require(options.min_points <= 2 * options.max_neighbors_per_side + 1,
          prefix + "min_points must not exceed 2 * max_neighbors_per_side + 1");
  require(std::isfinite(options.max_gap_m) && options.max_gap_m > 0.0,
          prefix + "max_gap_m must be a positive number of metres");
  require(std::isfinite(options.max_gap_range_m) && options.max_gap_range_m >= 0.0,
          prefix + "max_gap_range_m must be a number of metres >= 0 (0: max_gap_m alone)");
  require(std::isfinite(options.max_gap_incidence_rad) && options.max_gap_incidence_rad >= 0.0 &&
              options.max_gap_incidence_rad < 0.5 * M_PI,
          prefix + "max_gap_incidence_rad must be in [0, pi/2) radians (0: off)");
  require(std::isfinite(options.max_rms_m) && options.max_rms_m > 0.0,
          prefix + "max_rms_m must be a positive number of metres");
  require(std::isfinite(options.max_bend_sigmas) && options.max_bend_sigmas > 0.0,
          prefix + "max_bend_sigmas must be a positive number");
  require(options.min_points_one_sided >= 3, prefix + "min_points_one_sided must be at least 3");
  require(options.segment_fallback_max_surface_points >= 0,
          prefix + "segment_fallback_max_surface_points must be >= 0 (0: no limit)");
  require(std::isfinite(options.veiling_min_angle_rad) && options.veiling_min_angle_rad >= 0.0 &&
              options.veiling_min_angle_rad < 0.5 * M_PI,
          prefix + "veiling_min_angle_rad must be in [0, pi/2) radians");
  require(options.veiling_max_ray_gap >= 1, prefix + "veiling_max_ray_gap must be at least 1");
}

namespace {

/// Whether points k and k + 1 lie on different surfaces (a depth discontinuity): farther apart
/// than max_gap_m, than max_gap_range_m times the angle between neighbouring rays, and than that
/// angle times the nearer point's range over cos(max_gap_incidence_rad) (the spacing of
/// neighbouring rays' points on a surface seen at that incidence: r dtheta / cos(incidence)).
bool surfaceBreak(const ScanPoints& points, int k, const LineFitOptions& options)
{
  const double gap_m = (points.points_m[k + 1] - points.points_m[k]).norm();
  if (gap_m <= options.max_gap_m) {
    return false;
  }
  if (options.max_gap_range_m <= 0.0 || points.angles_rad.size() != points.size() ||
      points.ray_indices.size() != points.size()) {
    return true;
  }
  // The angle between neighbouring rays (not between these two points: dropped readings in
  // between do not widen the threshold).
  const int rays_apart = std::max(1, std::abs(points.ray_indices[k + 1] - points.ray_indices[k]));
  const double ray_spacing_rad =
      std::abs(points.angles_rad[k + 1] - points.angles_rad[k]) / static_cast<double>(rays_apart);
  double reach_m = options.max_gap_range_m;
  if (options.max_gap_incidence_rad > 0.0 && points.ranges_m.size() == points.size()) {
    const double near_m = std::min(points.ranges_m[k], points.ranges_m[k + 1]);
    reach_m = std::max(reach_m, near_m / std::cos(options.max_gap_incidence_rad));
  }
  return gap_m > reach_m * ray_spacing_rad;
}

/// A scan's surfaces (maximal runs of points without a depth discontinuity, surfaceBreak) and
/// the prefix moments of their points: the total-least-squares fit of any window of one surface
/// in constant time.
class SurfaceFits
{
public:
  SurfaceFits(const ScanPoints& points, const LineFitOptions& options)
      : points_(points),
        surface_start_(points.size(), 0),
        surface_end_(points.size(), static_cast<int>(points.size()) - 1),
        sums_(points.size())
  {
    const int n = static_cast<int>(points.size());
    for (int i = 1; i < n; ++i) {
      surface_start_[i] = surfaceBreak(points, i - 1, options) ? i : surface_start_[i - 1];
    }
    for (int i = n - 2; i >= 0; --i) {
      surface_end_[i] = surface_start_[i + 1] == surface_start_[i] ? surface_end_[i + 1] : i;
    }
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d p = points.points_m[i] - points.points_m[surface_start_[i]];
      const bool restart = surface_start_[i] == i;
      sums_.x[i + 1] = (restart ? 0.0 : sums_.x[i]) + p.x();
      sums_.y[i + 1] = (restart ? 0.0 : sums_.y[i]) + p.y();
      sums_.xx[i + 1] = (restart ? 0.0 : sums_.xx[i]) + p.x() * p.x();
      sums_.xy[i + 1] = (restart ? 0.0 : sums_.xy[i]) + p.x() * p.y();
      sums_.yy[i + 1] = (restart ? 0.0 : sums_.yy[i]) + p.y() * p.y();
    }
  }

  /// The first and last point of point i's surface.
  int surfaceStart(int i) const { return surface_start_[i]; }
  int surfaceEnd(int i) const { return surface_end_[i]; }

  /// Total-least-squares fit of points [first, last] of one surface from the prefix sums.
  WindowFit fit(int first, int last) const
  {
    WindowFit result;
    result.first = first;
    result.last = last;
    result.count = last - first + 1;
    const double k = static_cast<double>(result.count);
    const double sx = windowSum(sums_.x, first, last);
    const double sy = windowSum(sums_.y, first, last);
    const double mx = sx / k;
    const double my = sy / k;
    const double cxx = windowSum(sums_.xx, first, last) - sx * mx;
    const double cxy = windowSum(sums_.xy, first, last) - sx * my;
    const double cyy = windowSum(sums_.yy, first, last) - sy * my;
    // Eigen-decomposition of the 2x2 scatter matrix: principal axis angle and eigenvalues.
    const double half_trace = 0.5 * (cxx + cyy);
    const double half_difference = 0.5 * (cxx - cyy);
    const double radius = std::sqrt(half_difference * half_difference + cxy * cxy);
    result.across_m2 = std::max(0.0, half_trace - radius);
    result.along_m2 = half_trace + radius;
    // Normal = eigenvector of the smallest eigenvalue, from whichever row of (C - l I) is better
    // conditioned (no trigonometry: this runs three times per point).
    const double smallest = half_trace - radius;
    const Eigen::Vector2d from_x(cxy, smallest - cxx);
    const Eigen::Vector2d from_y(smallest - cyy, cxy);
    const Eigen::Vector2d& normal = from_x.squaredNorm() >= from_y.squaredNorm() ? from_x : from_y;
    const double norm = normal.norm();
    result.normal = norm > 0.0 ? Eigen::Vector2d(normal / norm) : Eigen::Vector2d::UnitY();
    result.centroid_m = points_.points_m[surface_start_[first]] + Eigen::Vector2d(mx, my);
    return result;
  }

private:
  /// Window sum over [a, b] of one surface: the prefix restarts at the surface's first point, so
  /// the sum is prefix[b + 1] minus prefix[a] unless a is that first point.
  double windowSum(const std::vector<double>& prefix, int a, int b) const
  {
    return prefix[b + 1] - (a == surface_start_[b] ? 0.0 : prefix[a]);
  }

  const ScanPoints& points_;
  std::vector<int> surface_start_;
  std::vector<int> surface_end_;
  PrefixMoments sums_;
};

/// Whether two fits of adjacent pieces differ in direction by more than max_bend_sigmas
/// standard deviations of that difference (pieces of fewer than 3 points never do).
bool bent(const WindowFit& first, const WindowFit& second, double max_bend_sigmas2)
{
  if (first.count < 3 || second.count < 3) {
    return false;
  }
  const double sine = first.normal.x() * second.normal.y() - first.normal.y() * second.normal.x();
  const double bend_rad = std::abs(sine);  // sin(bend) ~ bend for the small bends that matter
  // The noise level is the straighter piece's scatter: the bent piece's own scatter is
  // inflated by the bend and would hide it.
  // Floor: 0.1 mm, below any lidar's resolution (keeps noise-free data well-posed).
  const double noise_m2 = std::max(std::min(first.meanSquare(), second.meanSquare()), 1e-8);
  const double variance_rad2 = noise_m2 / first.along_m2 + noise_m2 / second.along_m2;
  return bend_rad * bend_rad > max_bend_sigmas2 * variance_rad2;
}

/// Slides the window [a, b] to point j (two pointers, amortised O(n)): its ends become the
/// farthest points within the radius, the count limit and j's surface.
void slideWindow(const ScanPoints& points, const SurfaceFits& surfaces, int j,
                 const LineFitOptions& options, double radius2_m2, int& a, int& b)
{
  const Eigen::Vector2d& p_j = points.points_m[j];
  a = std::max({a, j - options.max_neighbors_per_side, surfaces.surfaceStart(j)});
  while (a < j && (points.points_m[a] - p_j).squaredNorm() > radius2_m2) {
    ++a;
  }
  const int b_limit = std::min(j + options.max_neighbors_per_side, surfaces.surfaceEnd(j));
  b = std::max(b, j);
  b = std::min(b, b_limit);
  while (b + 1 <= b_limit && (points.points_m[b + 1] - p_j).squaredNorm() <= radius2_m2) {
    ++b;
  }
  while (b > j && (points.points_m[b] - p_j).squaredNorm() > radius2_m2) {
    --b;
  }
}

/// The line of point j, whose window is [a, b], into `chosen`; false when the point gets none.
/// A window too small for a fit falls back to Censi's segment; a window whose halves bend
/// against each other gives the straighter half.
bool chooseFit(const SurfaceFits& surfaces, int j, int a, int b, const LineFitOptions& options,
               double max_bend_sigmas2, WindowFit& chosen)
{
  const WindowFit centred = surfaces.fit(a, b);
  chosen = centred;
  if (centred.count < options.min_points) {
    // Too small or too sparse for a fit (a table leg, a far surface): Censi's segment, the
    // line through the point's immediate neighbours on the same surface.
    const int first = std::max(j - 1, surfaces.surfaceStart(j));
    const int last = std::min(j + 1, surfaces.surfaceEnd(j));
    const int surface_points = surfaces.surfaceEnd(j) - surfaces.surfaceStart(j) + 1;
    if (!options.segment_fallback || last - first + 1 < 2 ||
        (options.segment_fallback_max_surface_points > 0 &&
         surface_points > options.segment_fallback_max_surface_points)) {
      return false;
    }
    chosen = surfaces.fit(first, last);
  } else if (const WindowFit left = surfaces.fit(a, j), right = surfaces.fit(j, b);
             bent(left, right, max_bend_sigmas2)) {
    // Bend test: the halves on either side of the point must agree in direction within their
    // noise. A corner (or a curve) near the point makes them differ; then the straighter
    // half, which does not reach across the corner, is the point's surface, provided it
    // passes the same test itself (on a curve it does not: the point gets no line).
    chosen = left.meanSquare() <= right.meanSquare() ? left : right;
    const int middle = (chosen.first + chosen.last) / 2;
    if (chosen.count < options.min_points_one_sided ||
        bent(surfaces.fit(chosen.first, middle), surfaces.fit(middle, chosen.last),
             max_bend_sigmas2)) {
      return false;
    }
  }
  return true;
}

/// Stores `chosen` as point j's line: normal towards the sensor, centroid, spread, the extent
/// along the line (half a point spacing beyond its end points).
void storeLine(const ScanPoints& points, int j, const WindowFit& chosen,
               const LineFitOptions& options, ScanLines& lines)
{
  Eigen::Vector2d normal = chosen.normal;
  if (normal.dot(chosen.centroid_m) > 0.0) {
    normal = -normal;  // towards the sensor
  }
  lines.normals[j] = normal;
  lines.centroids_m[j] = chosen.centroid_m;
  lines.spread_m2[j] = chosen.along_m2;
  lines.first[j] = chosen.first;
  lines.last[j] = chosen.last;
  const Eigen::Vector2d tangent(-normal.y(), normal.x());
  const double along_first_m = tangent.dot(points.points_m[chosen.first] - chosen.centroid_m);
  const double along_last_m = tangent.dot(points.points_m[chosen.last] - chosen.centroid_m);
  const double half_spacing_m = 0.5 * std::abs(along_last_m - along_first_m) / (chosen.count - 1.0);
  lines.along_min_m[j] = std::min(along_first_m, along_last_m) - half_spacing_m;
  lines.along_max_m[j] = std::max(along_first_m, along_last_m) + half_spacing_m;
  lines.valid[j] = 1;
  lines.fitted[j] = chosen.count >= options.min_points_one_sided ? 1 : 0;
  ++lines.valid_count;
}

/// Lines of `n` points, none valid yet.
ScanLines emptyLines(int n)
{
  ScanLines lines;
  lines.normals.assign(n, Eigen::Vector2d::Zero());
  lines.centroids_m.assign(n, Eigen::Vector2d::Zero());
  lines.first.assign(n, 0);
  lines.last.assign(n, 0);
  lines.spread_m2.assign(n, 0.0);
  lines.along_min_m.assign(n, 0.0);
  lines.along_max_m.assign(n, 0.0);
  lines.valid.assign(n, 0);
  lines.fitted.assign(n, 0);
  return lines;
}

}  // namespace

ScanLines fitScanLines(const ScanPoints& points, const LineFitOptions& options)
{
  const int n = static_cast<int>(points.size());
  ScanLines lines = emptyLines(n);
  if (n == 0) {
    return lines;
  }
  const SurfaceFits surfaces(points, options);
  const double radius2_m2 = options.radius_m * options.radius_m;
  const double max_bend_sigmas2 = options.max_bend_sigmas * options.max_bend_sigmas;
  const double max_rms2_m2 = options.max_rms_m * options.max_rms_m;
  int a = 0;
  int b = 0;
  for (int j = 0; j < n; ++j) {
    slideWindow(points, surfaces, j, options, radius2_m2, a, b);
    lines.first[j] = a;
    lines.last[j] = b;
    WindowFit chosen;
    if (chooseFit(surfaces, j, a, b, options, max_bend_sigmas2, chosen) &&
        !(chosen.across_m2 > max_rms2_m2 * chosen.count)) {
      storeLine(points, j, chosen, options, lines);
    }
  }
  return lines;
}

}  // namespace odometry_calibration
