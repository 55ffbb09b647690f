#include "odometry_calibration/scan/nearest_point_search.h"

namespace odometry_calibration {

int NearestPointSearch::nearest(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                                double min_cosine, double max_distance_m, double* distance_m,
                                int hint) const
{
  const NearestPoint answer = find(query_m, query_normal, min_cosine, max_distance_m, hint, 0.0);
  if (distance_m != nullptr && answer.index >= 0) {
    *distance_m = answer.distance_m;
  }
  return answer.index;
}

int NearestPointSearch::nearestTracked(const Eigen::Vector2d& query_m,
                                       const Eigen::Vector2d& query_normal, double min_cosine,
                                       double max_distance_m, double margin_m, NearestTrack& track,
                                       int hint) const
{
  if (track.valid) {
    // Every point other than the last answer lies at least `clear_m` from the query now (the
    // triangle inequality: it was at least isolation_m from where the query was).
    const double clear_m = track.isolation_m - (query_m - track.query_m).norm();
    if (track.index < 0) {
      if (clear_m > max_distance_m) {
        return -1;  // still nothing within reach
      }
    } else {
      const double distance_m = (points_.points_m[track.index] - query_m).norm();
      if (distance_m < clear_m) {
        // The last answer is still the nearest point of all; it is the answer if it is still
        // compatible and within reach, and nothing is when it is out of reach.
        if (!(distance_m < max_distance_m)) {
          return -1;  // find() takes points strictly within max_distance_m
        }
        if (compatible(track.index, query_normal, min_cosine)) {
          return track.index;
        }
        if (clear_m > max_distance_m) {
          return -1;  // the others are out of reach
        }
      }
    }
  }
  const NearestPoint answer = find(query_m, query_normal, min_cosine, max_distance_m,
                                   track.valid ? track.index : hint, margin_m);
  track.valid = true;
  track.index = answer.index;
  track.query_m = query_m;
  track.isolation_m = answer.isolation_m;
  return answer.index;
}

}  // namespace odometry_calibration
