#include "odometry_calibration/scan/plicp_match.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>

#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/pcl_support.h"
#include "odometry_calibration/scan/plicp_matcher.h"
#include "odometry_calibration/scan/point_to_line_solver.h"

namespace odometry_calibration {
namespace {

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

/// Largest search margin (findCorrespondences), as a fraction of max_correspondence_distance_m:
/// wider margins cost more visits than they save.
constexpr double kMaxSearchMarginFraction = 0.04;

/// Whether two poses are equal within the convergence tolerances.
bool withinTolerance(const Pose2& a, const Pose2& b, const PlicpOptions& options)
{
  return std::hypot(a.x() - b.x(), a.y() - b.y()) < options.translation_tolerance_m &&
         std::abs(normalizeAngle(a.theta() - b.theta())) < options.rotation_tolerance_rad;
}

/// The last iterates of one match, for cycle detection, and whether each step held a direction
/// at the guess (by iteration modulo 16: a cycle spans at most 9 steps).
class IterationHistory
{
public:
  IterationHistory() { recent_.fill(Pose2(std::nan(""), std::nan(""), std::nan(""))); }

  /// Records whether the step of `iteration` held a direction at the guess.
  void recordStep(int iteration, const Degeneracy& degeneracy)
  {
    held_[iteration % held_.size()] = degeneracy.degenerate();
    if (degeneracy.degenerate()) {
      held_degeneracy_ = degeneracy;
    }
  }

  /// Moves on from T_ref_new, the pose `iteration` started at, to `next`. A pose equal to one a
  /// few steps back is a cycle: correspondences flip in and out of the trimmed set. The poses
  /// of the cycle are fixed points of equal merit: the match converged. Returns whether `next`
  /// closes a cycle; solutionHeld() then tells whether a step of the cycle (or, without a
  /// cycle, this step) held a direction.
  bool advance(int iteration, const Pose2& T_ref_new, const Pose2& next,
               const PlicpOptions& options)
  {
    bool cycle = false;
    int cycle_start = iteration;  // the first step of the cycle (this step when none)
    for (std::size_t slot = 0; slot < recent_.size(); ++slot) {
      if (withinTolerance(next, recent_[slot], options)) {
        cycle = true;
        cycle_start = std::min(cycle_start, recent_iteration_[slot]);
      }
    }
    solution_held_ = false;
    for (int k = cycle_start; k <= iteration; ++k) {
      solution_held_ = solution_held_ || held_[k % held_.size()];
    }
    recent_[iteration % recent_.size()] = T_ref_new;
    recent_iteration_[iteration % recent_.size()] = iteration;
    return cycle;
  }

  /// Whether the pose the iteration stops at comes from a held step (the last step, or any
  /// step of the cycle it stops in).
  bool solutionHeld() const { return solution_held_; }
  /// The last degeneracy a step held.
  const Degeneracy& heldDegeneracy() const { return held_degeneracy_; }

private:
  std::array<Pose2, 8> recent_;
  std::array<int, 8> recent_iteration_{};  // the iteration whose start each of recent_ is
  std::array<bool, 16> held_{};
  Degeneracy held_degeneracy_;
  bool solution_held_ = false;
};

/// The state of one match's iteration.
struct MatchState
{
  Pose2 T_ref_new;
  bool converged = false;
  Degeneracy last_degeneracy;  // the one the last step obeyed
  /// How far the pose may still be from the solution, as a displacement of the points: unknown
  /// at first (no adaptive trimming), then twice the last step.
  double pose_uncertainty_m = 0.0;
  IterationHistory history;
};

/// The search margin of an iteration [m]. The next steps move the points by about the last
/// one's displacement in all (PLICP converges superlinearly): searches that look twice
/// pose_uncertainty_m beyond their answer stay valid over them. The first step's size is
/// unknown: no margin (it would rarely hold).
double searchMargin(int iteration, double pose_uncertainty_m, const PlicpOptions& options)
{
  return iteration == 1
             ? 0.0
             : std::min(2.0 * pose_uncertainty_m,
                        kMaxSearchMarginFraction * options.max_correspondence_distance_m);
}

/// The failure of a match whose pose left the allowed correction from the guess, if it did.
std::optional<PlicpResult> correctionTooLarge(const PlicpResult& result,
                                              const Pose2& T_ref_new_guess,
                                              const PlicpOptions& options)
{
  const Pose2& T_ref_new = result.T_ref_new;
  const double correction_m =
      std::hypot(T_ref_new.x() - T_ref_new_guess.x(), T_ref_new.y() - T_ref_new_guess.y());
  const double correction_rad =
      std::abs(normalizeAngle(T_ref_new.theta() - T_ref_new_guess.theta()));
  if (!(correction_m > options.max_correction_translation_m ||
        correction_rad > options.max_correction_rotation_rad)) {
    return std::nullopt;
  }
  return failure(result, PlicpStatus::kCorrectionTooLarge,
                 "the match moved " + formatNumber(correction_m) + " m and " +
                     formatNumber(correction_rad) + " rad from the initial guess (limits " +
                     formatNumber(options.max_correction_translation_m) + " m, " +
                     formatNumber(options.max_correction_rotation_rad) +
                     " rad): the guess is too far off or the match is wrong");
}

/// One iteration of PLICP: correspondences at the current pose, trimmed, the closed-form step
/// (holding what the scene does not constrain at the guess), the cycle and convergence tests.
/// Returns the match's failure if the iteration fails.
std::optional<PlicpResult> iterate(PlicpMatcher& matcher, int iteration,
                                   const Pose2& T_ref_new_guess, const PlicpOptions& options,
                                   MatchState& state, PlicpResult& result)
{
  result.iterations = iteration;
  if (iteration == options.max_iterations / 2 + 1) {
    matcher.freezeTrimThreshold();
  }
  matcher.findCorrespondences(state.T_ref_new,
                              searchMargin(iteration, state.pose_uncertainty_m, options));
  matcher.trim(state.pose_uncertainty_m);
  if (matcher.kept().size() < static_cast<std::size_t>(options.min_correspondences)) {
    return failure(result, PlicpStatus::kTooFewCorrespondences,
                   "only " + std::to_string(matcher.kept().size()) +
                       " correspondences at iteration " + std::to_string(iteration) +
                       " (min_correspondences " + std::to_string(options.min_correspondences) +
                       "): the scans do not overlap near the initial guess");
  }
  matcher.buildSystem();
  const Degeneracy degeneracy = matcher.degeneracy(state.T_ref_new);
  if (degeneracy.direction == DegenerateDirection::kSeveral) {
    result.degeneracy = degeneracy;
    return failure(result, PlicpStatus::kUnconstrained, degeneracy.description);
  }
  state.last_degeneracy = degeneracy;
  state.history.recordStep(iteration, degeneracy);
  const std::optional<Pose2> next = matcher.step(constraintFor(degeneracy, T_ref_new_guess));
  if (!next) {
    return failure(result, PlicpStatus::kUnconstrained,
                   "the correspondences do not determine the motion (singular system)");
  }
  const Pose2& T_ref_new = state.T_ref_new;
  const double step_m = std::hypot(next->x() - T_ref_new.x(), next->y() - T_ref_new.y());
  const double step_rad = std::abs(normalizeAngle(next->theta() - T_ref_new.theta()));
  const bool cycle = state.history.advance(iteration, T_ref_new, *next, options);
  state.pose_uncertainty_m = 2.0 * matcher.pointDisplacement(step_m, step_rad);
  state.T_ref_new = *next;
  result.T_ref_new = *next;
  if (std::optional<PlicpResult> failed = correctionTooLarge(result, T_ref_new_guess, options)) {
    return failed;
  }
  state.converged = cycle || (step_m < options.translation_tolerance_m &&
                              step_rad < options.rotation_tolerance_rad);
  return std::nullopt;
}

/// The correspondences at the solution, trimmed without margin, and their statistics in
/// `result` (count, mean absolute residual, and the overlap: the fraction of the new scan's
/// surface points, those with a line of their own, within inlier_distance_m of a reference line).
/// Points without a line (foliage, clutter, a curve) are left out of both counts: they are off
/// any line wherever the scan is put, so counting them would make a cluttered scene look like a
/// wrong match (the Freiburg campus log: right matches at 20-30 % of all points).
void measureSolution(PlicpMatcher& matcher, const PreparedScan& current, const Pose2& T_ref_new,
                     const PlicpOptions& options, PlicpResult& result)
{
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
    inliers += current.lines.valid[static_cast<std::size_t>(c.current_index)] != 0 &&
                       std::abs(c.residual_m) <= options.inlier_distance_m
                   ? 1
                   : 0;
  }
  result.inlier_fraction =
      current.lines.valid_count == 0
          ? 0.0
          : static_cast<double>(inliers) / static_cast<double>(current.lines.valid_count);
}

/// The degeneracy reported at the solution (the system of the kept correspondences there).
Degeneracy solutionDegeneracy(PlicpMatcher& matcher, const MatchState& state)
{
  matcher.buildSystem();
  Degeneracy degeneracy = matcher.degeneracy(state.T_ref_new);
  if (degeneracy.direction == DegenerateDirection::kTranslation &&
      state.last_degeneracy.direction == DegenerateDirection::kTranslation) {
    // Report the axis the solution was held on (the re-analysis differs in round-off only).
    degeneracy = state.last_degeneracy;
  }
  // Near the degeneracy threshold the analysis can flip between iterations: a step holds the
  // weak direction at the guess, the next one does not, and the iteration stops (small step or
  // cycle) on a pose whose weak component is the guess's or lies between it and the solution.
  // The analysis at that pose may find the scene just constrained, yet the component was never
  // measured: the match is reported degenerate, as the held step found it (in the
  // sparse hall such matches were valid 3-4 cm and 6-15 mrad off, 7-9 sigma).
  if (!degeneracy.degenerate() && state.history.solutionHeld()) {
    degeneracy = state.history.heldDegeneracy();
  }
  return degeneracy;
}

/// The match's outcome once the iteration stopped: statistics, degeneracy, overlap and
/// covariance at the solution.
PlicpResult concludeMatch(PlicpMatcher& matcher, const PreparedScan& reference,
                          const PreparedScan& current, const PlicpOptions& options,
                          const MatchState& state, PlicpResult result)
{
  measureSolution(matcher, current, state.T_ref_new, options, result);
  if (!state.converged) {
    return failure(result, PlicpStatus::kNoConvergence,
                   "no convergence in " + std::to_string(options.max_iterations) +
                       " iterations (max_iterations)");
  }
  const std::vector<Correspondence>& kept = matcher.kept();
  if (kept.size() < static_cast<std::size_t>(options.min_correspondences)) {
    return failure(result, PlicpStatus::kTooFewCorrespondences,
                   "only " + std::to_string(kept.size()) + " correspondences at the solution");
  }
  result.degeneracy = solutionDegeneracy(matcher, state);
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
                                        state.T_ref_new, options.range_sigma_m);
  }
  if (result.degeneracy.degenerate()) {
    result.status = PlicpStatus::kDegenerate;
    result.message = result.degeneracy.description;
  } else {
    result.status = PlicpStatus::kValid;
  }
  return result;
}

/// The correspondence search over the reference scan; the kd-tree only in builds with PCL.
std::unique_ptr<NearestPointSearch> makeSearch(const PreparedScan& reference,
                                               CorrespondenceSearch kind)
{
  if (kind == CorrespondenceSearch::kAngularOrder)
    return makeAngularSearch(reference.points, reference.lines);
  if constexpr (kHavePcl) {
    return makeKdTreeSearch(reference.points, reference.lines);
  } else {
    throw std::invalid_argument(
        withoutPclMessage("PlicpOptions::correspondence_search kKdTree (the kd-tree search)"));
  }
}

}  // namespace

PlicpResult matchOnce(const PreparedScan& reference, const PreparedScan& current,
                      const Pose2& T_ref_new_guess, const PlicpOptions& options,
                      std::unique_ptr<NearestPointSearch>& search, const IterationStop& stop)
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
    search = makeSearch(reference, options.correspondence_search);
  }
  PlicpMatcher matcher(reference, current, options, *search);
  MatchState state;
  state.T_ref_new = T_ref_new_guess;
  state.pose_uncertainty_m = options.max_correspondence_distance_m;
  for (int iteration = 1; iteration <= options.max_iterations && !state.converged; ++iteration) {
    if (std::optional<PlicpResult> failed =
            iterate(matcher, iteration, T_ref_new_guess, options, state, result)) {
      return *failed;
    }
    if (stop && stop(state.T_ref_new, state.pose_uncertainty_m)) {
      return failure(result, PlicpStatus::kNoConvergence,
                     "stopped by the caller after iteration " + std::to_string(iteration));
    }
  }
  return concludeMatch(matcher, reference, current, options, state, result);
}

}  // namespace odometry_calibration
