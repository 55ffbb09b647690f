#include "odometry_calibration/scan/plicp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

#include <vector>

#include <Eigen/Geometry>

#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/point_to_line_solver.h"
#include "odometry_calibration/scan/veiling_points.h"

namespace odometry_calibration {
namespace {

/// The buffers of a Matcher, as long as the new scan. They live per thread and are reused by
/// the next match: allocating them for every match and handing the memory back to the system
/// afterwards (glibc trims the heap's top beyond 128 kB) costs up to a fifth of a 1081-ray
/// match in page faults.
struct MatcherBuffers
{
  std::vector<Correspondence> all;
  std::vector<Correspondence> kept;
  std::vector<double> magnitudes;
  std::vector<NearestTrack> tracks;  // per new point: its last search
};

/// Everything one match needs, built once per call. At most one Matcher per thread exists at a
/// time (it uses the thread's MatcherBuffers). `search` is over the reference scan's points.
class Matcher
{
public:
  Matcher(const PreparedScan& reference, const PreparedScan& current, const PlicpOptions& options,
          const NearestPointSearch& search)
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

  /// Matches every new point, transformed by T_ref_new, to the nearest reference point with a
  /// line whose direction is compatible; fills all_ with the residuals to those lines. A point
  /// whose last match provably still holds is not searched again (nearestTracked); a search
  /// looks `margin_m` [m] beyond its answer so that the answer keeps holding while the pose
  /// moves by less than about half of that.
  void findCorrespondences(const Pose2& T_ref_new, double margin_m)
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

  /// Keeps the correspondences of all_ that pass both trimmings into kept_. The adaptive
  /// threshold never drops below `pose_uncertainty_m` [m]: while the pose still moves, large
  /// residuals are the pose's error, not outliers, and dropping them would freeze the pose
  /// wherever it stands (typically at the initial guess).
  void trim(double pose_uncertainty_m)
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

  /// The trimming threshold of all_ [m]: the smaller of the fixed percentile (the largest
  /// residual still kept) and the adaptive threshold.
  double trimThreshold(double pose_uncertainty_m)
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

  /// The rank-th smallest |residual| of all_ (0-based) [m]. Ranks in the top quarter, as the
  /// fixed percentile's, come from a min-heap of the largest ones (one pass, mostly
  /// comparisons); others from a selection over all of them.
  double rankedMagnitude(std::size_t rank)
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

  /// From now on trims at the last threshold: the trimmed set no longer follows the residual
  /// quantiles, whose changes can keep the iteration cycling through nearby poses forever.
  void freezeTrimThreshold() { frozen_threshold_m_ = last_threshold_m_; }

  /// Accumulates the closed-form system of kept_ (Censi ICRA 2008) and the RMS radius of its
  /// new points (the lever arm of a rotation).
  void buildSystem()
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

  /// Closed-form step on the system of kept_ (buildSystem) under `constraint`.
  std::optional<Pose2> step(const StepConstraint& constraint) const
  {
    return system_.solve(constraint);
  }

  /// Degeneracy of the system of kept_ (buildSystem) at T_ref_new: the information matrix of
  /// pointToLineInformation(), taken from the system's normal equations.
  Degeneracy degeneracy(const Pose2& T_ref_new) const
  {
    return analyzeDegeneracy(system_.information(T_ref_new.theta()), lever_arm_m_,
                             options_.min_information_ratio);
  }

  /// Largest displacement of a new point [m] caused by a pose change of step_m [m] and
  /// step_rad [rad], at the RMS range of the new scan.
  double pointDisplacement(double step_m, double step_rad) const
  {
    return step_m + step_rad * rms_range_m_;
  }

  const std::vector<Correspondence>& all() const { return all_; }
  const std::vector<Correspondence>& kept() const { return kept_; }

private:
  static MatcherBuffers& buffers()
  {
    thread_local MatcherBuffers thread_buffers;
    return thread_buffers;
  }

  const PreparedScan& reference_;
  const PreparedScan& current_;
  const PlicpOptions& options_;
  const double cos_max_normal_angle_;
  const NearestPointSearch& search_;
  std::vector<Correspondence>& all_;
  std::vector<Correspondence>& kept_;
  std::vector<double>& magnitudes_;
  std::vector<NearestTrack>& tracks_;
  PointToLineSystem system_;
  double lever_arm_m_ = 1.0;
  double rms_range_m_ = 0.0;
  double last_threshold_m_ = 0.0;
  double frozen_threshold_m_ = 0.0;  // > 0 once frozen
};

/// Holds what the scene does not constrain at its initial-guess value.
StepConstraint constraintFor(const Degeneracy& degeneracy, const Pose2& T_ref_new_guess)
{
  StepConstraint constraint;
  if (degeneracy.direction == DegenerateDirection::kTranslation) {
    constraint.fix_translation_along_axis = true;
    constraint.fixed_axis_ref = degeneracy.axis_ref;
    constraint.fixed_along_m =
        degeneracy.axis_ref.dot(Eigen::Vector2d(T_ref_new_guess.x(), T_ref_new_guess.y()));
  } else if (degeneracy.direction == DegenerateDirection::kRotation) {
    constraint.fix_rotation = true;
    constraint.fixed_theta_rad = T_ref_new_guess.theta();
  }
  return constraint;
}

PlicpResult failure(PlicpResult result, PlicpStatus status, const std::string& message)
{
  result.status = status;
  result.message = message;
  result.covariance.setZero();
  return result;
}

}  // namespace

const char* toString(PlicpStatus status)
{
  switch (status) {
    case PlicpStatus::kValid:
      return "valid";
    case PlicpStatus::kDegenerate:
      return "degenerate";
    case PlicpStatus::kTooFewPoints:
      return "too few points";
    case PlicpStatus::kTooFewCorrespondences:
      return "too few correspondences";
    case PlicpStatus::kNoConvergence:
      return "no convergence";
    case PlicpStatus::kCorrectionTooLarge:
      return "correction too large";
    case PlicpStatus::kPoorOverlap:
      return "poor overlap";
    case PlicpStatus::kUnconstrained:
      return "unconstrained";
  }
  return "unknown";
}

PreparedScan prepareScan(const Scan& scan, const LineFitOptions& options,
                         const SensorVelocity& velocity)
{
  validate(options);
  PreparedScan prepared;
  prepared.points = scanToPoints(scan, velocity);
  if (options.veiling_min_angle_rad > 0.0) {
    prepared.points = removePoints(prepared.points,
                                   findVeilingPoints(prepared.points, options.veiling_min_angle_rad,
                                                     options.veiling_max_ray_gap));
  }
  prepared.lines = fitScanLines(prepared.points, options);
  return prepared;
}

namespace {

/// Largest search margin (findCorrespondences), as a fraction of max_correspondence_distance_m:
/// wider margins cost more visits than they save.
constexpr double kMaxSearchMarginFraction = 0.04;

/// One match from one initial guess (matchScans without the ambiguity check). Builds the
/// search over the reference scan into `search` unless an earlier match of the same scans did.
PlicpResult matchOnce(const PreparedScan& reference, const PreparedScan& current,
                      const Pose2& T_ref_new_guess, const PlicpOptions& options,
                      std::unique_ptr<NearestPointSearch>& search)
{
  PlicpResult result;
  result.T_ref_new = T_ref_new_guess;
  const auto min_points = static_cast<std::size_t>(options.min_points);
  if (reference.lines.valid_count < min_points || current.points.size() < min_points) {
    return failure(result, PlicpStatus::kTooFewPoints,
                   "too few usable points: the reference scan has " +
                       std::to_string(reference.lines.valid_count) +
                       " points on straight surfaces, the new scan " +
                       std::to_string(current.points.size()) + " usable readings; min_points is " +
                       std::to_string(options.min_points));
  }

  if (!search) {
    search = options.correspondence_search == CorrespondenceSearch::kKdTree
                 ? makeKdTreeSearch(reference.points, reference.lines)
                 : makeAngularSearch(reference.points, reference.lines);
  }
  Matcher matcher(reference, current, options, *search);
  Pose2 T_ref_new = T_ref_new_guess;
  // The last few iterates, for cycle detection.
  std::array<Pose2, 8> recent;
  recent.fill(Pose2(std::nan(""), std::nan(""), std::nan("")));
  std::array<int, 8> recent_iteration{};  // the iteration whose start each of recent is
  // Whether each step held a direction at the guess (by iteration modulo 16: a cycle spans at
  // most 9 steps), the last degeneracy a step held, and whether the pose the iteration stops at
  // comes from a held step (the last step, or any step of the cycle it stops in).
  std::array<bool, 16> held{};
  Degeneracy held_degeneracy;
  bool solution_held = false;
  bool converged = false;
  Degeneracy last_degeneracy;  // the one the last step obeyed
  // How far the pose may still be from the solution, as a displacement of the points: unknown
  // at first (no adaptive trimming), then twice the last step.
  double pose_uncertainty_m = options.max_correspondence_distance_m;
  for (int iteration = 1; iteration <= options.max_iterations && !converged; ++iteration) {
    result.iterations = iteration;
    if (iteration == options.max_iterations / 2 + 1) {
      matcher.freezeTrimThreshold();
    }
    // The next steps move the points by about the last one's displacement in all (PLICP
    // converges superlinearly): searches that look twice pose_uncertainty_m beyond their answer
    // stay valid over them. The first step's size is unknown: no margin (it would rarely hold).
    const double margin_m =
        iteration == 1 ? 0.0
                       : std::min(2.0 * pose_uncertainty_m,
                                  kMaxSearchMarginFraction * options.max_correspondence_distance_m);
    matcher.findCorrespondences(T_ref_new, margin_m);
    matcher.trim(pose_uncertainty_m);
    if (matcher.kept().size() < static_cast<std::size_t>(options.min_correspondences)) {
      return failure(result, PlicpStatus::kTooFewCorrespondences,
                     "only " + std::to_string(matcher.kept().size()) +
                         " correspondences at iteration " + std::to_string(iteration) +
                         " (min_correspondences " + std::to_string(options.min_correspondences) +
                         "): the scans do not overlap near the initial guess");
    }
    matcher.buildSystem();
    const Degeneracy degeneracy = matcher.degeneracy(T_ref_new);
    if (degeneracy.direction == DegenerateDirection::kSeveral) {
      result.degeneracy = degeneracy;
      return failure(result, PlicpStatus::kUnconstrained, degeneracy.description);
    }
    last_degeneracy = degeneracy;
    held[iteration % held.size()] = degeneracy.degenerate();
    if (degeneracy.degenerate()) {
      held_degeneracy = degeneracy;
    }
    const std::optional<Pose2> next = matcher.step(constraintFor(degeneracy, T_ref_new_guess));
    if (!next) {
      return failure(result, PlicpStatus::kUnconstrained,
                     "the correspondences do not determine the motion (singular system)");
    }
    const double step_m = std::hypot(next->x() - T_ref_new.x(), next->y() - T_ref_new.y());
    const double step_rad = std::abs(normalizeAngle(next->theta() - T_ref_new.theta()));
    // A pose equal to one a few steps back is a cycle: correspondences flip in and out of the
    // trimmed set. The poses of the cycle are fixed points of equal merit: the match converged.
    bool cycle = false;
    int cycle_start = iteration;  // the first step of the cycle (this step when none)
    for (std::size_t slot = 0; slot < recent.size(); ++slot) {
      const Pose2& earlier = recent[slot];
      if (std::hypot(next->x() - earlier.x(), next->y() - earlier.y()) <
              options.translation_tolerance_m &&
          std::abs(normalizeAngle(next->theta() - earlier.theta())) <
              options.rotation_tolerance_rad) {
        cycle = true;
        cycle_start = std::min(cycle_start, recent_iteration[slot]);
      }
    }
    solution_held = false;
    for (int k = cycle_start; k <= iteration; ++k) {
      solution_held = solution_held || held[k % held.size()];
    }
    recent[iteration % recent.size()] = T_ref_new;
    recent_iteration[iteration % recent.size()] = iteration;
    pose_uncertainty_m = 2.0 * matcher.pointDisplacement(step_m, step_rad);
    T_ref_new = *next;
    result.T_ref_new = T_ref_new;
    const double correction_m =
        std::hypot(T_ref_new.x() - T_ref_new_guess.x(), T_ref_new.y() - T_ref_new_guess.y());
    const double correction_rad =
        std::abs(normalizeAngle(T_ref_new.theta() - T_ref_new_guess.theta()));
    if (correction_m > options.max_correction_translation_m ||
        correction_rad > options.max_correction_rotation_rad) {
      return failure(result, PlicpStatus::kCorrectionTooLarge,
                     "the match moved " + formatNumber(correction_m) + " m and " +
                         formatNumber(correction_rad) + " rad from the initial guess (limits " +
                         formatNumber(options.max_correction_translation_m) + " m, " +
                         formatNumber(options.max_correction_rotation_rad) +
                         " rad): the guess is too far off or the match is wrong");
    }
    converged = cycle || (step_m < options.translation_tolerance_m &&
                          step_rad < options.rotation_tolerance_rad);
  }

  // Statistics, degeneracy and covariance at the solution.
  matcher.findCorrespondences(T_ref_new, 0.0);
  matcher.trim(0.0);
  const std::vector<Correspondence>& kept = matcher.kept();
  result.correspondence_count = static_cast<int>(kept.size());
  double residual_sum_m = 0.0;
  for (const Correspondence& c : kept) {
    residual_sum_m += std::abs(c.residual_m);
  }
  result.mean_residual_m = kept.empty() ? 0.0 : residual_sum_m / static_cast<double>(kept.size());
  std::size_t inliers = 0;
  for (const Correspondence& c : matcher.all()) {
    inliers += std::abs(c.residual_m) <= options.inlier_distance_m ? 1 : 0;
  }
  result.inlier_fraction =
      static_cast<double>(inliers) / static_cast<double>(current.points.size());

  if (!converged) {
    return failure(result, PlicpStatus::kNoConvergence,
                   "no convergence in " + std::to_string(options.max_iterations) +
                       " iterations (max_iterations)");
  }
  if (kept.size() < static_cast<std::size_t>(options.min_correspondences)) {
    return failure(result, PlicpStatus::kTooFewCorrespondences,
                   "only " + std::to_string(kept.size()) + " correspondences at the solution");
  }
  matcher.buildSystem();
  result.degeneracy = matcher.degeneracy(T_ref_new);
  if (result.degeneracy.direction == DegenerateDirection::kTranslation &&
      last_degeneracy.direction == DegenerateDirection::kTranslation) {
    // Report the axis the solution was held on (the re-analysis differs in round-off only).
    result.degeneracy = last_degeneracy;
  }
  // Near the degeneracy threshold the analysis can flip between iterations: a step holds the
  // weak direction at the guess, the next one does not, and the iteration stops (small step or
  // cycle) on a pose whose weak component is the guess's or lies between it and the solution.
  // The analysis at that pose may find the scene just constrained, yet the component was never
  // measured: the match is reported degenerate, as the held step found it (issue 16: in the
  // sparse hall such matches were valid 3-4 cm and 6-15 mrad off, 7-9 sigma).
  if (!result.degeneracy.degenerate() && solution_held) {
    result.degeneracy = held_degeneracy;
  }
  if (result.degeneracy.direction == DegenerateDirection::kSeveral) {
    return failure(result, PlicpStatus::kUnconstrained, result.degeneracy.description);
  }
  if (result.inlier_fraction < options.min_inlier_fraction) {
    return failure(
        result, PlicpStatus::kPoorOverlap,
        "only " + formatNumber(100.0 * result.inlier_fraction) +
            " % of the new scan's points lie within " + formatNumber(options.inlier_distance_m) +
            " m of a reference surface (min_inlier_fraction " +
            formatNumber(options.min_inlier_fraction) + "): probably a wrong local minimum");
  }
  if (options.compute_covariance) {
    result.covariance = plicpCovariance(reference.points, reference.lines, current.points, kept,
                                        T_ref_new, options.range_sigma_m);
  }
  if (result.degeneracy.degenerate()) {
    result.status = PlicpStatus::kDegenerate;
    result.message = result.degeneracy.description;
  } else {
    result.status = PlicpStatus::kValid;
  }
  return result;
}

}  // namespace

PlicpResult matchScans(const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options)
{
  validate(options);
  std::unique_ptr<NearestPointSearch> search;  // built once, shared by the ambiguity check
  PlicpResult result = matchOnce(reference, current, T_ref_new_guess, options, search);
  if (needsAmbiguityCheck(result, options)) {
    result = checkAmbiguity(std::move(result), options, [&](const Pose2& start) {
      return matchOnce(reference, current, start, options, search);
    });
  }
  return result;
}

PlicpResult matchScans(const Scan& reference, const Scan& current, const Pose2& T_ref_new_guess,
                       const PlicpOptions& options)
{
  validate(options);
  return matchScans(prepareScan(reference, options.line_fit),
                    prepareScan(current, options.line_fit), T_ref_new_guess, options);
}

}  // namespace odometry_calibration
