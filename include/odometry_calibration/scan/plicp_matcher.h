// The working state of one PLICP match (plicp_match.h): correspondences of the new scan's
// points with the reference scan's lines, their trimming, the closed-form system of the kept
// ones (Censi ICRA 2008), its degeneracy and step.
#pragma once

#include <optional>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/point_to_line_solver.h"

namespace odometry_calibration {

/// Everything one match needs, built once per call. At most one PlicpMatcher per thread exists
/// at a time (it uses the thread's buffers). `search` is over the reference scan's points; the
/// scans, options and search must outlive the matcher.
class PlicpMatcher
{
public:
  PlicpMatcher(const PreparedScan& reference, const PreparedScan& current,
               const PlicpOptions& options, const NearestPointSearch& search);
  PlicpMatcher(const PlicpMatcher&) = delete;
  PlicpMatcher& operator=(const PlicpMatcher&) = delete;

  /// Matches every new point, transformed by T_ref_new, to the nearest reference point with a
  /// line whose direction is compatible; fills all_ with the residuals to those lines. A point
  /// whose last match provably still holds is not searched again (nearestTracked); a search
  /// looks `margin_m` [m] beyond its answer so that the answer keeps holding while the pose
  /// moves by less than about half of that.
  void findCorrespondences(const Pose2& T_ref_new, double margin_m);

  /// Keeps the correspondences of all_ that pass both trimmings into kept_. The adaptive
  /// threshold never drops below `pose_uncertainty_m` [m]: while the pose still moves, large
  /// residuals are the pose's error, not outliers, and dropping them would freeze the pose
  /// wherever it stands (typically at the initial guess).
  void trim(double pose_uncertainty_m);

  /// From now on trims at the last threshold: the trimmed set no longer follows the residual
  /// quantiles, whose changes can keep the iteration cycling through nearby poses forever.
  void freezeTrimThreshold() { frozen_threshold_m_ = last_threshold_m_; }

  /// Accumulates the closed-form system of kept_ (Censi ICRA 2008) and the RMS radius of its
  /// new points (the lever arm of a rotation).
  void buildSystem();

  /// Closed-form step on the system of kept() (buildSystem) under `constraint`.
  std::optional<Pose2> step(const StepConstraint& constraint) const
  {
    return system_.solve(constraint);
  }

  /// Degeneracy of the system of kept_ (buildSystem) at T_ref_new: the information matrix of
  /// pointToLineInformation(), taken from the system's normal equations.
  Degeneracy degeneracy(const Pose2& T_ref_new) const;

  /// Largest displacement of a new point [m] caused by a pose change of step_m [m] and
  /// step_rad [rad], at the RMS range of the new scan.
  double pointDisplacement(double step_m, double step_rad) const
  {
    return step_m + step_rad * rms_range_m_;
  }

  /// The correspondences found (findCorrespondences) and those kept by the trimming (trim).
  const std::vector<Correspondence>& all() const { return all_; }
  const std::vector<Correspondence>& kept() const { return kept_; }

private:
  struct Buffers;
  static Buffers& buffers();

  /// The trimming threshold of all_ [m]: the smaller of the fixed percentile (the largest
  /// residual still kept) and the adaptive threshold.
  double trimThreshold(double pose_uncertainty_m);
  /// The rank-th smallest |residual| of all_ (0-based) [m]. Ranks in the top quarter, as the
  /// fixed percentile's, come from a min-heap of the largest ones (one pass, mostly
  /// comparisons); others from a selection over all of them.
  double rankedMagnitude(std::size_t rank);

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

}  // namespace odometry_calibration
