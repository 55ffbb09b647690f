#include <algorithm>
#include <cmath>
#include <limits>

#include "odometry_calibration/scan/nearest_point_search.h"

namespace odometry_calibration {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;
/// Coverage beyond 270 degrees by less than this still counts as 270 degrees (no wrap-around)
/// [rad]: a 270-degree scan's float32 angle increment and minimum put its last ray up to a few
/// 1e-7 rad beyond 1.5 pi, and the wrap-around walks cost a bearing (atan2) per query and a
/// wrapped index per visited point. A point more than 180 degrees away unwrapped then lies at
/// least 90 degrees - 1e-5 rad away, no nearer than |q| cos(1e-5) = |q| (1 - 5e-11), which the
/// walks' angular bound treats like a point 90 degrees away; queries beyond the field of view
/// are walked from both of its ends (find).
constexpr double kWrapTolerance_rad = 1e-5;

/// Angle wrapped into [0, 2 pi) [rad]: exact steps for angles within a few turns, fmod beyond
/// (a scan's angles are validated, but a loop must never run 1e30 times).
double wrapPositive(double angle_rad)
{
  if (std::abs(angle_rad) > 8.0 * kTwoPi)
    angle_rad = std::fmod(angle_rad, kTwoPi);
  while (angle_rad >= kTwoPi) {
    angle_rad -= kTwoPi;
  }
  while (angle_rad < 0.0) {
    angle_rad += kTwoPi;
  }
  return angle_rad;
}

/// atan2 to within about 1e-5 rad (a degree-11 odd polynomial for atan on [0, 1], then the
/// octant): only to guess where a search starts; the exact start comes from cross products.
double approximateAtan2(double y, double x)
{
  const double ax = std::abs(x), ay = std::abs(y);
  const double big = std::max(ax, ay);
  if (big == 0.0)
    return 0.0;
  const double t = std::min(ax, ay) / big;
  const double t2 = t * t;
  double a =
      t * (0.99997726 +
           t2 * (-0.33262347 +
                 t2 * (0.19354346 + t2 * (-0.11643287 + t2 * (0.05265332 - 0.01172120 * t2)))));
  if (ay > ax)
    a = 0.5 * M_PI - a;
  if (x < 0.0)
    a = M_PI - a;
  return y < 0.0 ? -a : a;
}

class AngularSearch final : public NearestPointSearch
{
public:
  AngularSearch(const ScanPoints& points, const ScanLines& lines)
      : NearestPointSearch(points, lines), position_(points.size(), -1)
  {
    points_.reserve(lines.valid_count);
    angles_rad_.reserve(lines.valid_count);
    indices_.reserve(lines.valid_count);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (lines.valid[i] != 0) {
        const Eigen::Vector2d& p = points.points_m[i];
        const Eigen::Vector2d& n = lines.normals[i];
        // The bearing of the point itself (the walks' bounds rely on it).
        const Eigen::Vector2d d = p / p.norm();
        position_[i] = static_cast<int>(points_.size());
        points_.push_back(
            {p.x(), p.y(), d.x(), d.y(), n.x(), n.y(), lines.fitted[i] != 0, p.norm()});
        angles_rad_.push_back(points.angles_rad[i]);
        indices_.push_back(static_cast<int>(i));
      }
    }
    // Beyond 270 degrees of coverage a query may sit between the last and the first ray, so the
    // walks wrap around; below it a point more than 180 degrees away (unwrapped) is always more
    // than 90 degrees away for real, hence no nearer than |q|, and the walks can stop at the ends
    // (both ends for a query beyond the field of view: find).
    wraps_ = !angles_rad_.empty() &&
             angles_rad_.back() - angles_rad_.front() > 1.5 * M_PI + kWrapTolerance_rad;
    buildJumpTables();
  }

  NearestPoint find(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                    double min_cosine, double max_distance_m, int hint,
                    double margin_m) const override
  {
    const int n = static_cast<int>(points_.size());
    if (n == 0) {
      return {};
    }
    // With a zero query normal every point passes (0 >= 0).
    Search search;
    search.qx = query_m.x();
    search.qy = query_m.y();
    search.query_norm_m = query_m.norm();
    search.qnx = query_normal.x();
    search.qny = query_normal.y();
    search.min_dot = min_cosine * query_normal.norm();
    search.best_distance2_m2 = max_distance_m * max_distance_m;
    search.best_distance_m = max_distance_m;
    search.margin_m = margin_m;
    search.reach_m = max_distance_m + margin_m;
    search.reach2_m2 = search.reach_m * search.reach_m;
    const int hint_position =
        hint >= 0 && hint < static_cast<int>(position_.size()) ? position_[hint] : -1;
    int start = -1;
    if (hint_position >= 0) {
      // The hint is a candidate: the walks can stop as soon as nothing nearer is possible.
      consider(search, hint_position);
      start = startNear(search, hint_position);
    }
    if (start < 0) {
      start = startFromBearing(search);
    }
    walk(search, start, +1);
    walk(search, start - 1, -1);
    if (!wraps_ && n > 1 && (start == 0 || start == n - 1)) {
      // A query beyond either end of the field of view (behind the sensor) may lie nearer to
      // the other end's rays than to this end's, which the walks from this end never reach.
      // Walks from the other end stop at once when it is out of reach.
      if (start == 0)
        walk(search, n - 1, -1);
      else
        walk(search, 0, +1);
    }
    NearestPoint answer;
    // Points not visited lie beyond the reach, visited ones at least at the runner-up's distance.
    answer.isolation_m = std::min(std::sqrt(search.runner_up2_m2), search.reach_m);
    if (search.best >= 0) {
      answer.index = indices_[search.best];
      answer.distance_m = search.best_distance_m;
    }
    return answer;
  }

private:
  /// A usable reference point, its unit bearing and its line's normal, packed for the walks.
  struct Point
  {
    double x, y;     // [m]
    double dx, dy;   // unit bearing
    double nx, ny;   // unit normal
    bool fitted;     // a segment's normal (not fitted) is too noisy to test: it passes every test
    double range_m;  // |(x, y)|
  };

  /// Jump tables (as in Censi's CSM): for each position, the next position up (down) whose
  /// range is larger, and the next whose range is smaller; n (-1) when there is none. A point
  /// whose range differs from |q| by more than the best distance found cannot beat it, nor can
  /// any point up to the next one whose range is on the other side of it, so a walk skips them.
  void buildJumpTables()
  {
    const int n = static_cast<int>(points_.size());
    up_bigger_.resize(n);
    up_smaller_.resize(n);
    down_bigger_.resize(n);
    down_smaller_.resize(n);
    // The ranges side by side (points_ holds 8 numbers per point).
    std::vector<double> range_m(n);
    for (int k = 0; k < n; ++k) {
      range_m[k] = points_[k].range_m;
    }
    // Nearest position above (below) k with a larger (smaller) range, or n (-1) when none: from
    // the neighbour, jump along the neighbours' own answers while they are no larger (smaller),
    // as every position skipped that way is no larger (smaller) either (amortised O(n)).
    for (int k = n - 1; k >= 0; --k) {
      int bigger = k + 1;
      while (bigger < n && range_m[bigger] <= range_m[k]) {
        bigger = up_bigger_[bigger];
      }
      up_bigger_[k] = bigger;
      int smaller = k + 1;
      while (smaller < n && range_m[smaller] >= range_m[k]) {
        smaller = up_smaller_[smaller];
      }
      up_smaller_[k] = smaller;
    }
    for (int k = 0; k < n; ++k) {
      int bigger = k - 1;
      while (bigger >= 0 && range_m[bigger] <= range_m[k]) {
        bigger = down_bigger_[bigger];
      }
      down_bigger_[k] = bigger;
      int smaller = k - 1;
      while (smaller >= 0 && range_m[smaller] >= range_m[k]) {
        smaller = down_smaller_[smaller];
      }
      down_smaller_[k] = smaller;
    }
  }

  struct Search
  {
    double qx, qy;             // the query [m]
    double query_norm_m;       // |q|
    double qnx, qny;           // query normal; zero: no compatibility test
    double min_dot;            // a point's normal . query normal must reach this
    double best_distance2_m2;  // starts at the squared limit
    int best = -1;
    double best_distance_m;  // its square root
    // How far the walks look: the best distance plus the margin (and its square) [m], [m^2].
    double margin_m;
    double reach_m;
    double reach2_m2;
    // Smallest squared distance of a visited point other than the best [m^2].
    double runner_up2_m2 = std::numeric_limits<double>::infinity();
    // The query's bearing unwrapped into [first, first + 2 pi) like the sorted ray angles,
    // computed once when needed (NaN until then).
    double bearing_rad = std::numeric_limits<double>::quiet_NaN();
  };

  /// The query's exact bearing (one atan2 per query at most).
  double bearingOf(Search& search) const
  {
    if (std::isnan(search.bearing_rad)) {
      const double first_rad = angles_rad_.front();
      search.bearing_rad = first_rad + wrapPositive(std::atan2(search.qy, search.qx) - first_rad);
    }
    return search.bearing_rad;
  }

  /// q x d_k: > 0 when the query lies clockwise of point k's bearing (within 180 degrees).
  double crossWithBearing(const Search& search, int k) const
  {
    return points_[k].dx * search.qy - points_[k].dy * search.qx;
  }

  /// The first position whose bearing is not below the query's (lower_bound of the bearing),
  /// found by stepping from the hint with cross products (no trigonometry); -1 when the hint is
  /// too far in angle for that, or the query lies beyond the last ray (the caller then uses
  /// startFromBearing).
  int startNear(const Search& search, int k) const
  {
    const int n = static_cast<int>(points_.size());
    if (wraps_ || points_[k].dx * search.qx + points_[k].dy * search.qy <= 0.0) {
      return -1;
    }
    if (crossWithBearing(search, k) > 0.0) {
      // The query is counter-clockwise of k: move up while it stays so.
      while (k + 1 < n && crossWithBearing(search, k + 1) > 0.0 &&
             points_[k + 1].dx * search.qx + points_[k + 1].dy * search.qy > 0.0) {
        ++k;
      }
      if (k + 1 >= n || crossWithBearing(search, k + 1) > 0.0) {
        return -1;  // beyond the last ray, or too far round: let the bearing decide
      }
      return k + 1;
    }
    while (k > 0 && crossWithBearing(search, k - 1) <= 0.0 &&
           points_[k - 1].dx * search.qx + points_[k - 1].dy * search.qy > 0.0) {
      --k;
    }
    if (k > 0 && crossWithBearing(search, k - 1) <= 0.0) {
      return -1;
    }
    return k;
  }

  /// The first position whose bearing is not below the query's, from its angle: guessed from
  /// an approximate bearing and made exact with cross products (startNear), or, where that
  /// cannot decide (wrap-around scans, beyond the field of view), from the exact bearing.
  int startFromBearing(Search& search) const
  {
    const int n = static_cast<int>(points_.size());
    const double first_rad = angles_rad_.front();
    if (!wraps_) {
      const double guess_rad =
          first_rad + wrapPositive(approximateAtan2(search.qy, search.qx) - first_rad);
      const int guess =
          static_cast<int>(std::lower_bound(angles_rad_.begin(), angles_rad_.end(), guess_rad) -
                           angles_rad_.begin());
      const int start = startNear(search, std::min(guess, n - 1));
      if (start >= 0)
        return start;
    }
    const double bearing_rad = bearingOf(search);
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
    return start;
  }

  /// Takes point k as the best one if it is nearer and compatible.
  void consider(Search& search, int k) const
  {
    const Point& p = points_[k];
    const double ex = p.x - search.qx;
    const double ey = p.y - search.qy;
    const double distance2_m2 = ex * ex + ey * ey;
    if (distance2_m2 < search.best_distance2_m2 &&
        (!p.fitted || p.nx * search.qnx + p.ny * search.qny >= search.min_dot)) {
      if (search.best >= 0) {
        search.runner_up2_m2 = std::min(search.runner_up2_m2, search.best_distance2_m2);
      }
      search.best_distance2_m2 = distance2_m2;
      search.best_distance_m = std::sqrt(distance2_m2);
      search.best = k;
      search.reach_m = search.best_distance_m + search.margin_m;
      search.reach2_m2 = search.reach_m * search.reach_m;
    } else if (k != search.best) {
      search.runner_up2_m2 = std::min(search.runner_up2_m2, distance2_m2);
    }
  }

  /// Visits points from `from` in direction `step` (+1 up, -1 down) while the angular lower
  /// bound on their distance can still beat the best one found.
  void walk(Search& search, int from, int step) const
  {
    if (!wraps_) {
      walkWithJumps(search, from, step);
      return;
    }
    const int n = static_cast<int>(points_.size());
    const double bearing_rad = bearingOf(search);
    for (int visited = 0; visited < n; ++visited) {
      const int k = (((from + step * visited) % n) + n) % n;
      // Each walk covers its own half circle; the other walk covers the rest.
      const double separation_rad = wrapPositive(step * (angles_rad_[k] - bearing_rad));
      if ((separation_rad >= M_PI && visited > 0) || angularBoundReached(search, k)) {
        return;
      }
      consider(search, k);
    }
  }

  /// walk() without wrap-around, skipping runs of points whose range alone rules them out.
  void walkWithJumps(Search& search, int k, int step) const
  {
    const int n = static_cast<int>(points_.size());
    const std::vector<int>& bigger = step > 0 ? up_bigger_ : down_bigger_;
    const std::vector<int>& smaller = step > 0 ? up_smaller_ : down_smaller_;
    while (k >= 0 && k < n && !angularBoundReached(search, k)) {
      consider(search, k);
      const double range_m = points_[k].range_m;
      if (range_m > search.query_norm_m + search.reach_m) {
        k = smaller[k];  // everything up to there is even farther out
      } else if (range_m < search.query_norm_m - search.reach_m) {
        k = bigger[k];  // everything up to there is even farther in
      } else {
        k += step;
      }
    }
  }

  /// Whether no point from k on (away from the query's bearing) lies within the reach (the best
  /// distance plus the margin):
  /// the distance from the query to the ray through point k bounds the distance of every point
  /// whose bearing differs more: |q| sin(d) below 90 degrees, |q| beyond.
  bool angularBoundReached(const Search& search, int k) const
  {
    const Point& p = points_[k];
    const double along = search.qx * p.dx + search.qy * p.dy;
    const double bound_m =
        along > 0.0 ? std::abs(search.qx * p.dy - search.qy * p.dx) : search.query_norm_m;
    return bound_m * bound_m >= search.reach2_m2;
  }

  std::vector<Point> points_;
  std::vector<double> angles_rad_;
  std::vector<int> indices_;   // reference index of each position
  std::vector<int> position_;  // position of each reference index, -1 when not usable
  std::vector<int> up_bigger_, up_smaller_, down_bigger_, down_smaller_;  // jump tables
  bool wraps_ = false;
};

}  // namespace

std::unique_ptr<NearestPointSearch> makeAngularSearch(const ScanPoints& points,
                                                      const ScanLines& lines)
{
  return std::make_unique<AngularSearch>(points, lines);
}

}  // namespace odometry_calibration
