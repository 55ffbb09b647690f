// Nearest-neighbour search among the reference scan's points, the inner loop of ICP.
//
// Two implementations answer the same question exactly (the nearest usable reference point
// with a compatible normal within a distance, ties aside):
//  - angular: the reference points are sorted by ray angle, so the search starts at the query's
//    bearing and walks outwards; a point whose bearing differs by d from the query's lies at
//    least |q| sin(d) from it (|q| once d >= 90 deg), which ends each walk early. This is the
//    idea behind the correspondence search of Censi's CSM (ICRA 2008, Sec. V), with an exact
//    stopping bound instead of its jump tables.
//  - kd-tree: PCL's FLANN kd-tree over the same points.
// PlicpOptions::correspondence_search picks one; see bench/plicp_bench.cpp for their speed.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/scan/scan_lines.h"

namespace odometry_calibration {

/// Finds the usable reference point nearest to a query point given in the reference frame,
/// optionally only among points whose surface normal is compatible with the query's.
class NearestPointSearch
{
public:
  virtual ~NearestPointSearch() = default;

  /// Index (into the reference ScanPoints) of the usable point nearest to `query_m` [m] within
  /// `max_distance_m` [m], or -1 when there is none. When `query_normal` is non-zero, points
  /// whose normal n satisfies n . query_normal < min_cosine are skipped (a different surface:
  /// the nearest point of the right surface may lie a little farther). `distance_m` receives the
  /// distance when not null. `hint` (a reference index, or -1) is a point likely to be near the
  /// answer, e.g. the previous ICP iteration's: it speeds the search up, never changes the answer
  /// (ties aside).
  virtual int nearest(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                      double min_cosine, double max_distance_m, double* distance_m,
                      int hint = -1) const = 0;
};

/// Angular-order search over the points with lines.valid[i] != 0, using lines.normals for the
/// compatibility test. Keeps references to `points` and `lines` (which must outlive it). O(n) to
/// build; a query visits the points within the angular bound.
std::unique_ptr<NearestPointSearch> makeAngularSearch(const ScanPoints& points,
                                                      const ScanLines& lines);

/// PCL kd-tree (FLANN) search over the same points: a radius search, then the nearest compatible
/// point. O(n log n) to build.
std::unique_ptr<NearestPointSearch> makeKdTreeSearch(const ScanPoints& points,
                                                     const ScanLines& lines);

}  // namespace odometry_calibration
