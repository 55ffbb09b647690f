#include "odometry_calibration/scan/plicp_matcher.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <Eigen/Geometry>

namespace odometry_calibration {

/// The buffers of a PlicpMatcher, as long as the new scan. They live per thread and are reused
/// by the next match: allocating them for every match and handing the memory back to the
/// system afterwards (glibc trims the heap's top beyond 128 kB) costs up to a fifth of a
/// 1081-ray match in page faults.
struct PlicpMatcher::Buffers
{
  std::vector<Correspondence> all;
  std::vector<Correspondence> kept;
  std::vector<double> magnitudes;
  std::vector<NearestTrack> tracks;  // per new point: its last search
};

PlicpMatcher::Buffers& PlicpMatcher::buffers()
{
  thread_local Buffers thread_buffers;
  return thread_buffers;
}

PlicpMatcher::PlicpMatcher(const PreparedScan& reference, const PreparedScan& current,
                           const PlicpOptions& options, const NearestPointSearch& search)
    : reference_(reference),
      current_(current),
      options_(options),
      cos_max_normal_angle_(std::cos(options.max_normal_angle_rad)),
      search_(search),
      all_(buffers().all),
      kept_(buffers().kept),
      magnitudes_(buffers().magnitudes),
      tracks_(buffers().tracks)
{
  double range2_sum_m2 = 0.0;
  for (const double range_m : current.points.ranges_m) {
    range2_sum_m2 += range_m * range_m;
  }
  rms_range_m_ = current.points.empty()
                     ? 0.0
                     : std::sqrt(range2_sum_m2 / static_cast<double>(current.points.size()));
  all_.clear();
  kept_.clear();
  all_.reserve(current.points.size());
  kept_.reserve(current.points.size());
  magnitudes_.reserve(current.points.size());
  tracks_.assign(current.points.size(), NearestTrack());
}

void PlicpMatcher::findCorrespondences(const Pose2& T_ref_new, double margin_m)
{
  all_.clear();
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(T_ref_new.theta()).toRotationMatrix();
  const Eigen::Vector2d t(T_ref_new.x(), T_ref_new.y());
  const ScanPoints& points = current_.points;
  const ScanLines& lines = current_.lines;
  const ScanLines& reference_lines = reference_.lines;
  int last_match = -1;  // a new point's first search starts at its predecessor's match
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d q = R * points.points_m[i] + t;
    // The new point's own line, if it has one, must face the same way as the reference's
    // (the same surface seen from the same side).
    const Eigen::Vector2d query_normal =
        lines.fitted[i] != 0 ? Eigen::Vector2d(R * lines.normals[i]) : Eigen::Vector2d::Zero();
    const int j = search_.nearestTracked(q, query_normal, cos_max_normal_angle_,
                                         options_.max_correspondence_distance_m, margin_m,
                                         tracks_[i], last_match);
    if (j < 0) {
      continue;
    }
    last_match = j;
    const Eigen::Vector2d& normal = reference_lines.normals[j];
    const Eigen::Vector2d offset = q - reference_lines.centroids_m[j];
    const double along_m = normal.x() * offset.y() - normal.y() * offset.x();  // tangent . offset
    if (along_m < reference_lines.along_min_m[j] - options_.surface_extent_margin_m ||
        along_m > reference_lines.along_max_m[j] + options_.surface_extent_margin_m) {
      continue;  // beyond the end of the observed surface
    }
    all_.push_back({static_cast<int>(i), j, normal.dot(offset)});
  }
}

void PlicpMatcher::trim(double pose_uncertainty_m)
{
  kept_.clear();
  const std::size_t n = all_.size();
  if (n == 0) {
    return;
  }
  const double threshold_m =
      frozen_threshold_m_ > 0.0 ? frozen_threshold_m_ : trimThreshold(pose_uncertainty_m);
  last_threshold_m_ = threshold_m;
  for (const Correspondence& c : all_) {
    if (std::abs(c.residual_m) <= threshold_m) {
      kept_.push_back(c);
    }
  }
}

double PlicpMatcher::trimThreshold(double pose_uncertainty_m)
{
  const std::size_t n = all_.size();
  auto rankOf = [n](double fraction) {
    return static_cast<std::size_t>(
        std::clamp(std::ceil(fraction * static_cast<double>(n)) - 1.0, 0.0, n - 1.0));
  };
  const std::size_t fixed_rank = rankOf(options_.trim_keep_fraction);
  const double fixed_m = rankedMagnitude(fixed_rank);
  // The adaptive threshold matters only when it can fall below the fixed one: not when its
  // floor already reaches it (then its quantile need not be selected at all).
  const double floor_m = std::max(options_.adaptive_trim_floor_m, pose_uncertainty_m);
  if (floor_m >= fixed_m) {
    return fixed_m;
  }
  // Nor when multiplier times the quantile reaches it, i.e. when at most adaptive_rank
  // residuals stay below it after multiplying (a count, no selection; exact, as multiplying
  // by a positive number keeps the order).
  const std::size_t adaptive_rank = rankOf(options_.adaptive_trim_quantile);
  std::size_t below = 0;
  for (const Correspondence& c : all_) {
    below += options_.adaptive_trim_multiplier * std::abs(c.residual_m) < fixed_m ? 1 : 0;
  }
  if (below <= adaptive_rank) {
    return fixed_m;
  }
  const double adaptive_m =
      std::max(floor_m, options_.adaptive_trim_multiplier * rankedMagnitude(adaptive_rank));
  return std::min(fixed_m, adaptive_m);
}

double PlicpMatcher::rankedMagnitude(std::size_t rank)
{
  const std::size_t n = all_.size();
  const std::size_t from_top = n - rank;  // the answer is the from_top-th largest
  if (4 * from_top <= n) {
    magnitudes_.clear();
    for (const Correspondence& c : all_) {
      const double magnitude = std::abs(c.residual_m);
      if (magnitudes_.size() < from_top) {
        magnitudes_.push_back(magnitude);
        std::push_heap(magnitudes_.begin(), magnitudes_.end(), std::greater<double>());
      } else if (magnitude > magnitudes_.front()) {
        std::pop_heap(magnitudes_.begin(), magnitudes_.end(), std::greater<double>());
        magnitudes_.back() = magnitude;
        std::push_heap(magnitudes_.begin(), magnitudes_.end(), std::greater<double>());
      }
    }
    return magnitudes_.front();
  }
  magnitudes_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    magnitudes_[k] = std::abs(all_[k].residual_m);
  }
  std::nth_element(magnitudes_.begin(), magnitudes_.begin() + rank, magnitudes_.end());
  return magnitudes_[rank];
}

void PlicpMatcher::buildSystem()
{
  system_ = PointToLineSystem();
  double radius2_sum_m2 = 0.0;
  for (const Correspondence& c : kept_) {
    const Eigen::Vector2d& p = current_.points.points_m[c.current_index];
    system_.add(p, reference_.lines.centroids_m[c.reference_index],
                reference_.lines.normals[c.reference_index]);
    radius2_sum_m2 += p.squaredNorm();
  }
  lever_arm_m_ =
      kept_.empty() ? 1.0 : std::sqrt(radius2_sum_m2 / static_cast<double>(kept_.size()));
}

Degeneracy PlicpMatcher::degeneracy(const Pose2& T_ref_new) const
{
  return analyzeDegeneracy(system_.information(T_ref_new.theta()), lever_arm_m_,
                           options_.min_information_ratio);
}

}  // namespace odometry_calibration
