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

ScanLines fitScanLines(const ScanPoints& points, const LineFitOptions& options)
{
  const int n = static_cast<int>(points.size());
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
  if (n == 0) {
    return lines;
  }

  // Surfaces: maximal runs of points whose consecutive gaps stay below max_gap_m.
  std::vector<int> surface_start(n, 0);
  for (int i = 1; i < n; ++i) {
    const bool gap = (points.points_m[i] - points.points_m[i - 1]).norm() > options.max_gap_m;
    surface_start[i] = gap ? i : surface_start[i - 1];
  }
  std::vector<int> surface_end(n, n - 1);
  for (int i = n - 2; i >= 0; --i) {
    surface_end[i] = surface_start[i + 1] == surface_start[i] ? surface_end[i + 1] : i;
  }

  PrefixMoments sums(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points.points_m[i] - points.points_m[surface_start[i]];
    const bool restart = surface_start[i] == i;
    sums.x[i + 1] = (restart ? 0.0 : sums.x[i]) + p.x();
    sums.y[i + 1] = (restart ? 0.0 : sums.y[i]) + p.y();
    sums.xx[i + 1] = (restart ? 0.0 : sums.xx[i]) + p.x() * p.x();
    sums.xy[i + 1] = (restart ? 0.0 : sums.xy[i]) + p.x() * p.y();
    sums.yy[i + 1] = (restart ? 0.0 : sums.yy[i]) + p.y() * p.y();
  }
  // Window sums over [a, b] of one surface: the prefix restarts at the surface's first point, so
  // the sum is prefix[b + 1] minus prefix[a] unless a is that first point.
  auto windowSum = [&](const std::vector<double>& prefix, int a, int b) {
    return prefix[b + 1] - (a == surface_start[b] ? 0.0 : prefix[a]);
  };

  // Total-least-squares fit of points [first, last] of one surface from the prefix sums.
  auto fit = [&](int first, int last) {
    WindowFit result;
    result.first = first;
    result.last = last;
    result.count = last - first + 1;
    const double k = static_cast<double>(result.count);
    const double sx = windowSum(sums.x, first, last);
    const double sy = windowSum(sums.y, first, last);
    const double mx = sx / k;
    const double my = sy / k;
    const double cxx = windowSum(sums.xx, first, last) - sx * mx;
    const double cxy = windowSum(sums.xy, first, last) - sx * my;
    const double cyy = windowSum(sums.yy, first, last) - sy * my;
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
    result.centroid_m = points.points_m[surface_start[first]] + Eigen::Vector2d(mx, my);
    return result;
  };

  const double radius2_m2 = options.radius_m * options.radius_m;
  const double max_bend_sigmas2 = options.max_bend_sigmas * options.max_bend_sigmas;
  // Whether two fits of adjacent pieces differ in direction by more than max_bend_sigmas
  // standard deviations of that difference (pieces of fewer than 3 points never do).
  auto bent = [&](const WindowFit& first, const WindowFit& second) {
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
  };

  const double max_rms2_m2 = options.max_rms_m * options.max_rms_m;
  int a = 0;
  int b = 0;
  for (int j = 0; j < n; ++j) {
    // Two pointers: the window [a, b] slides with j (amortised O(n)). The window's ends are the
    // farthest points within the radius, the count limit and the surface.
    const Eigen::Vector2d& p_j = points.points_m[j];
    a = std::max({a, j - options.max_neighbors_per_side, surface_start[j]});
    while (a < j && (points.points_m[a] - p_j).squaredNorm() > radius2_m2) {
      ++a;
    }
    b = std::max(b, j);
    b = std::min(b, std::min(j + options.max_neighbors_per_side, surface_end[j]));
    while (b + 1 <= std::min(j + options.max_neighbors_per_side, surface_end[j]) &&
           (points.points_m[b + 1] - p_j).squaredNorm() <= radius2_m2) {
      ++b;
    }
    while (b > j && (points.points_m[b] - p_j).squaredNorm() > radius2_m2) {
      --b;
    }
    lines.first[j] = a;
    lines.last[j] = b;
    const WindowFit centred = fit(a, b);
    WindowFit chosen = centred;
    if (centred.count < options.min_points) {
      // Too small or too sparse for a fit (a table leg, a far surface): Censi's segment, the
      // line through the point's immediate neighbours on the same surface.
      const int first = std::max(j - 1, surface_start[j]);
      const int last = std::min(j + 1, surface_end[j]);
      const int surface_points = surface_end[j] - surface_start[j] + 1;
      if (!options.segment_fallback || last - first + 1 < 2 ||
          (options.segment_fallback_max_surface_points > 0 &&
           surface_points > options.segment_fallback_max_surface_points)) {
        continue;
      }
      chosen = fit(first, last);
    } else if (const WindowFit left = fit(a, j), right = fit(j, b); bent(left, right)) {
      // Bend test: the halves on either side of the point must agree in direction within their
      // noise. A corner (or a curve) near the point makes them differ; then the straighter
      // half, which does not reach across the corner, is the point's surface, provided it
      // passes the same test itself (on a curve it does not: the point gets no line).
      chosen = left.meanSquare() <= right.meanSquare() ? left : right;
      const int middle = (chosen.first + chosen.last) / 2;
      if (chosen.count < options.min_points_one_sided ||
          bent(fit(chosen.first, middle), fit(middle, chosen.last))) {
        continue;
      }
    }
    if (chosen.across_m2 > max_rms2_m2 * chosen.count) {
      continue;
    }
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
    const double half_spacing_m =
        0.5 * std::abs(along_last_m - along_first_m) / (chosen.count - 1.0);
    lines.along_min_m[j] = std::min(along_first_m, along_last_m) - half_spacing_m;
    lines.along_max_m[j] = std::max(along_first_m, along_last_m) + half_spacing_m;
    lines.valid[j] = 1;
    lines.fitted[j] = chosen.count >= options.min_points_one_sided ? 1 : 0;
    ++lines.valid_count;
  }
  return lines;
}

}  // namespace odometry_calibration
