#include <algorithm>
#include <cmath>

#include "odometry_calibration/scan/nearest_point_search.h"

namespace odometry_calibration {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

/// Angle wrapped into [0, 2 pi) [rad].
double wrapPositive(double angle_rad)
{
  angle_rad = std::fmod(angle_rad, kTwoPi);
  return angle_rad < 0.0 ? angle_rad + kTwoPi : angle_rad;
}

class AngularSearch final : public NearestPointSearch
{
public:
  AngularSearch(const ScanPoints& points, const ScanLines& lines)
  {
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (lines.valid[i] != 0) {
        normals_.push_back(lines.normals[i]);
        fitted_.push_back(lines.fitted[i]);
        angles_rad_.push_back(points.angles_rad[i]);
        points_m_.push_back(points.points_m[i]);
        directions_.push_back(points.directions[i]);
        indices_.push_back(static_cast<int>(i));
      }
    }
    // Beyond 270 degrees of coverage a query may sit between the last and the first ray, so the
    // walks wrap around; below it a point more than 180 degrees away (unwrapped) is always more
    // than 90 degrees away for real, hence no nearer than |q|, and the walks can stop at the ends.
    wraps_ = !angles_rad_.empty() && angles_rad_.back() - angles_rad_.front() > 1.5 * M_PI;
  }

  int nearest(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
              double min_cosine, double max_distance_m, double* distance_m) const override
  {
    const int n = static_cast<int>(angles_rad_.size());
    if (n == 0) {
      return -1;
    }
    const double first_rad = angles_rad_.front();
    // Bearing of the query, unwrapped into [first, first + 2 pi) like the sorted ray angles.
    const double bearing_rad =
        first_rad + wrapPositive(std::atan2(query_m.y(), query_m.x()) - first_rad);
    int start =
        static_cast<int>(std::lower_bound(angles_rad_.begin(), angles_rad_.end(), bearing_rad) -
                         angles_rad_.begin());
    if (start == n) {
      if (wraps_) {
        start = 0;
      } else {
        // Beyond the last ray: begin at whichever end of the field of view is nearer in angle.
        const double past_last_rad = bearing_rad - angles_rad_.back();
        const double before_first_rad = first_rad + kTwoPi - bearing_rad;
        start = past_last_rad <= before_first_rad ? n - 1 : 0;
      }
    }

    // With a zero query normal every point passes (0 >= 0).
    Search search{query_m,
                  query_m.norm(),
                  query_normal,
                  min_cosine * query_normal.norm(),
                  max_distance_m * max_distance_m,
                  -1};
    walk(search, start, +1, bearing_rad);
    walk(search, start - 1, -1, bearing_rad);
    if (search.best < 0) {
      return -1;
    }
    if (distance_m != nullptr) {
      *distance_m = std::sqrt(search.best_distance2_m2);
    }
    return indices_[search.best];
  }

private:
  struct Search
  {
    Eigen::Vector2d query_m;
    double query_norm_m;
    Eigen::Vector2d query_normal;  // zero: no compatibility test
    double min_dot;                // a point's normal . query_normal must reach this
    double best_distance2_m2;      // starts at the squared limit
    int best;
  };

  /// Visits points from `from` in direction `step` (+1 up, -1 down) while the angular lower
  /// bound on their distance can still beat the best one found.
  void walk(Search& search, int from, int step, double bearing_rad) const
  {
    const int n = static_cast<int>(angles_rad_.size());
    for (int visited = 0; visited < n; ++visited) {
      int k = from + step * visited;
      if (wraps_) {
        k = ((k % n) + n) % n;
        // Each walk covers its own half circle; the other walk covers the rest.
        const double separation_rad = wrapPositive(step * (angles_rad_[k] - bearing_rad));
        if (separation_rad >= M_PI && visited > 0) {
          return;
        }
      } else if (k < 0 || k >= n) {
        return;
      }
      const Eigen::Vector2d& direction = directions_[k];
      const double along = search.query_m.dot(direction);
      // Distance from the query to the ray through point k, a lower bound for every point
      // whose bearing differs more: |q| sin(d) below 90 degrees, |q| beyond.
      const double bound_m =
          along > 0.0
              ? std::abs(search.query_m.x() * direction.y() - search.query_m.y() * direction.x())
              : search.query_norm_m;
      if (bound_m * bound_m >= search.best_distance2_m2) {
        return;
      }
      const double distance2_m2 = (points_m_[k] - search.query_m).squaredNorm();
      if (distance2_m2 < search.best_distance2_m2 &&
          (fitted_[k] == 0 || normals_[k].dot(search.query_normal) >= search.min_dot)) {
        search.best_distance2_m2 = distance2_m2;
        search.best = k;
      }
    }
  }

  std::vector<double> angles_rad_;
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> points_m_;
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> directions_;
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> normals_;
  // A segment's normal (not fitted) is too noisy to test against: it passes every test.
  std::vector<std::uint8_t> fitted_;
  std::vector<int> indices_;
  bool wraps_ = false;
};

}  // namespace

std::unique_ptr<NearestPointSearch> makeAngularSearch(const ScanPoints& points,
                                                      const ScanLines& lines)
{
  return std::make_unique<AngularSearch>(points, lines);
}

}  // namespace odometry_calibration
