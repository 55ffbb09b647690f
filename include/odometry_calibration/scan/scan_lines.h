// Local line fits along a scan: the robust surface normals of the point-to-line metric.
//
// PLICP (Censi ICRA 2008) takes the line through the two reference points nearest to a query.
// With centimetre range noise and millimetre ray spacing that line's normal is off by tens of
// degrees, which both biases the match and, through the covariance of Censi ICRA 2007, invents
// information along featureless walls. Here every point gets a total-least-squares line fitted to
// its neighbours along the scan (a window bounded by a radius, a neighbour count and depth
// discontinuities). Near a corner the window's two halves disagree in direction, and the half
// that does not reach across the corner is used; a window that is still not straight (a curve,
// clutter) leaves the point without a line, so it is never used as a reference surface. Points
// of surfaces too small for a fit (a table leg) fall back to Censi's two-point segment.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// How the local lines are fitted. Defaults suit 0.25-0.5 degree scanners with ~1 cm noise.
struct LineFitOptions
{
  /// Neighbours farther than this from the point are not in its window [m].
  double radius_m = 0.12;
  /// At most this many neighbours on each side of the point [points].
  int max_neighbors_per_side = 24;
  /// A window needs at least this many points (the point included) [points], >= 3.
  int min_points = 5;
  /// Consecutive points farther apart than this start a new surface (depth discontinuity) [m]
  double max_gap_m = 0.2;
  /// ... unless they are no farther apart than the arc between two neighbouring rays at this
  /// range [m], >= 0 (0: max_gap_m alone). The gap threshold is max(max_gap_m, max_gap_range_m
  /// * ray spacing [rad]): 0.2 m at 0.25 and 0.4 deg rays (unchanged), 0.24 m at 0.5 deg, 0.49 m
  /// at 1 deg, 0.65 m at 1.33 deg. On sparse scanners a fixed 0.2 m cuts every wall beyond
  /// 0.2 m / spacing (11.5 m at 1 deg) into one-point surfaces, which get no line and are never
  /// matched: on the real FHW museum log (180 rays) 65 of 180 points per scan, and the far
  /// points are what pins the heading down (FHW median heading error on the pairs
  /// both matchers accept 0.342 -> 0.278 deg, CSM 0.271; docs/benchmarks.md).
  double max_gap_range_m = 28.0;
  /// ... and unless they are no farther apart than neighbouring rays' points on a surface seen at
  /// up to this incidence angle (from the surface normal) [rad], in [0, pi/2); 0: off. The
  /// threshold grows with the nearer point's range r: r * ray spacing / cos(angle), 2.9 times
  /// the arc at 70 deg. Beyond max_gap_range_m / 2.9 (9.6 m) it exceeds the fixed arc: far
  /// surfaces outdoors (the Freiburg campus log, 0.5 deg rays, walls and trees at 20-50 m, 0.17-
  /// 0.44 m apart) stay surfaces instead of one-point surfaces without a line
  /// (docs/scan_matching.md, "Real scans").
  double max_gap_incidence_rad = 70.0 * M_PI / 180.0;
  /// Largest RMS distance of the window's points from the fitted line [m]; beyond it the window
  /// is not straight (a corner, clutter) and the point gets no line.
  double max_rms_m = 0.02;
  /// Bend test: when the lines fitted to the window's halves left and right of the point differ
  /// in direction by more than this many standard deviations of that difference [-], the window
  /// straddles a corner or a curve and the straighter half is used instead.
  double max_bend_sigmas = 3.0;
  /// A half window used after a bend needs at least this many points [points], >= 3.
  int min_points_one_sided = 4;
  /// Points of surfaces too small or sparse for a fit (fewer than min_points in the window)
  /// get the line through their immediate neighbours, as in Censi's PLICP: small objects (legs,
  /// posts) then still constrain the match, at the price of noisier normals.
  bool segment_fallback = true;
  /// ... but only on surfaces (runs of points between depth discontinuities) of at most this
  /// many points [points], >= 0; 0: on any surface. A limit (e.g. 4) leaves the points of long
  /// surfaces whose window is too sparse (far walls, rays more than radius_m / 2 apart) without
  /// a line: a segment across two noisy far readings has a normal tens of degrees off. With
  /// range noise growing with the range (5 mm + 0.5 % of r) such segments make the simulated
  /// office read +0.3 to +0.4 % long, and a limit of 4 removes that; on the real Mines log the
  /// limit moves the matched distance from -1.80 % to -2.41 % of the nominal odometry, so it is
  /// not the default (docs/scan_matching.md, "Under simulated sensor effects").
  int segment_fallback_max_surface_points = 0;
  /// Scan preparation (prepareScan, before the fits): of two points of neighbouring rays whose
  /// connecting segment makes less than this angle with the nearer one's ray, the farther is a
  /// veiling point (a mixed pixel at a depth step, or the step's far edge) and is dropped
  /// (veiling_points.h) [rad], in [0, pi/2); 0 keeps every point.
  double veiling_min_angle_rad = 0.0;
  /// ... neighbouring: at most this many rays apart (dropped readings in between) [rays], >= 1.
  int veiling_max_ray_gap = 2;
};

/// Throws std::invalid_argument naming the first invalid option (prefix e.g. "line_fit.").
void validate(const LineFitOptions& options, const std::string& prefix = "line_fit.");

/// The fitted line of each point of a ScanPoints (same indexing). Entries of points without a
/// line (valid[i] == 0) are zero.
struct ScanLines
{
  /// Unit normal of the line, pointing towards the sensor [-].
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> normals;
  /// Centroid of the window: the point of the line the residual is measured from [m].
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> centroids_m;
  std::vector<int> first;  ///< first point of the window (inclusive)
  std::vector<int> last;   ///< last point of the window (inclusive)
  /// Sum of squared along-line offsets of the window's points from the centroid [m^2]; with the
  /// count it gives the line's sensitivity to each reading (Censi ICRA 2007 covariance).
  std::vector<double> spread_m2;
  /// Extent of the window along the line: along-line offsets from the centroid of its first and
  /// last points, widened by half the mean point spacing [m]. A query whose foot falls outside
  /// lies beyond the observed surface (e.g. on a part the reference scan did not see).
  std::vector<double> along_min_m;
  std::vector<double> along_max_m;
  std::vector<std::uint8_t> valid;  ///< 1 when the point has a line
  /// 1 when the line is a fit over a window (a reliable normal), 0 for a two- or three-point
  /// segment (segment_fallback) or no line.
  std::vector<std::uint8_t> fitted;
  std::size_t valid_count = 0;  ///< number of points with a line

  std::size_t size() const { return valid.size(); }
};

/// Fits a total-least-squares line (centroid and principal axis of the window's scatter matrix)
/// to every point's window of neighbours. O(n) with prefix sums.
ScanLines fitScanLines(const ScanPoints& points, const LineFitOptions& options);

}  // namespace odometry_calibration
