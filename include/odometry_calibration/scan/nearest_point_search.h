// Nearest-neighbour search among the reference scan's points, the inner loop of ICP.
//
// Two implementations answer the same question exactly (the nearest usable reference point
// with a compatible normal within a distance, ties aside):
//  - angular: the reference points are sorted by ray angle, so the search starts at the query's
//    bearing and walks outwards; a point whose bearing differs by d from the query's lies at
//    least |q| sin(d) from it (|q| once d >= 90 deg), which ends each walk early. This is the
//    idea behind the correspondence search of Censi's CSM (ICRA 2008, Sec. V), with an exact
//    stopping bound instead of its jump tables.
//  - kd-tree: PCL's FLANN kd-tree over the same points (only in builds with PCL, pcl_support.h;
//    without it matchScans() refuses it).
// PlicpOptions::correspondence_search picks one; see bench/plicp_bench.cpp for their speed.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/scan/scan_lines.h"

namespace odometry_calibration {

/// A search's answer: the point, its distance, and how isolated it is.
struct NearestPoint
{
  int index = -1;           ///< reference index of the answer, -1 when there is none
  double distance_m = 0.0;  ///< its distance from the query [m] (0 when none)
  /// Every usable reference point other than the answer, compatible or not, lies at least this
  /// far from the query [m] (>= 0; a lower bound, not the exact second distance).
  double isolation_m = 0.0;
};

/// What the last search for one moving query established (nearestTracked): the answer, where
/// the query was then, and the answer's isolation there.
struct NearestTrack
{
  bool valid = false;
  int index = -1;
  Eigen::Vector2d query_m = Eigen::Vector2d::Zero();
  double isolation_m = 0.0;
};

/// Finds the usable reference point nearest to a query point given in the reference frame,
/// optionally only among points whose surface normal is compatible with the query's.
class NearestPointSearch
{
public:
  /// Keeps references to `points` and `lines`, which must outlive the search.
  NearestPointSearch(const ScanPoints& points, const ScanLines& lines)
      : points_(points), lines_(lines)
  {
  }
  virtual ~NearestPointSearch() = default;

  /// The usable point nearest to `query_m` [m] within `max_distance_m` [m] (index -1 when there
  /// is none). When `query_normal` is non-zero, points with a fitted line (lines.fitted) whose
  /// normal n satisfies n . query_normal < min_cosine |query_normal| are skipped (a different
  /// surface: the nearest point of the right surface may lie a little farther). `hint` (a
  /// reference index, or -1) is a point likely to be near the answer, e.g. the previous ICP
  /// iteration's: it speeds the search up, never changes the answer (ties aside). The search
  /// looks `margin_m` [m] beyond the answer's distance (and beyond max_distance_m when there is
  /// no answer), so that isolation_m reaches the answer's distance plus margin_m unless another
  /// point lies nearer than that; margin 0 gives the plain search.
  virtual NearestPoint find(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                            double min_cosine, double max_distance_m, int hint,
                            double margin_m) const = 0;

  /// Index of the answer of find() with no margin, or -1; `distance_m` receives its distance
  /// when not null.
  int nearest(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
              double min_cosine, double max_distance_m, double* distance_m, int hint = -1) const;

  /// The answer of find() for a query that moves a little between calls (a new point over the
  /// ICP iterations), without searching while the last answer provably still holds: when the
  /// query has moved by delta since `track` was searched, every other point lies at least
  /// isolation - delta away, so an answer nearer than that (and still compatible) is still the
  /// nearest. Otherwise searches (hint: the last answer, or `hint` for a new track; margin
  /// `margin_m` [m]) and updates `track`. Exact: the same answer as find(), ties aside.
  int nearestTracked(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                     double min_cosine, double max_distance_m, double margin_m, NearestTrack& track,
                     int hint = -1) const;

protected:
  /// Whether reference point k may match a query with this normal (the rule of find()).
  bool compatible(int k, const Eigen::Vector2d& query_normal, double min_cosine) const
  {
    return lines_.fitted[k] == 0 ||
           lines_.normals[k].dot(query_normal) >= min_cosine * query_normal.norm();
  }

  const ScanPoints& points_;
  const ScanLines& lines_;
};

/// Angular-order search over the points with lines.valid[i] != 0, using lines.normals for the
/// compatibility test. Keeps references to `points` and `lines` (which must outlive it). O(n) to
/// build; a query visits the points within the angular bound.
std::unique_ptr<NearestPointSearch> makeAngularSearch(const ScanPoints& points,
                                                      const ScanLines& lines);

/// PCL kd-tree (FLANN) search over the same points: a radius search, then the nearest compatible
/// point. O(n log n) to build. Defined only in builds with PCL (kHavePcl, pcl_support.h).
std::unique_ptr<NearestPointSearch> makeKdTreeSearch(const ScanPoints& points,
                                                     const ScanLines& lines);

}  // namespace odometry_calibration
