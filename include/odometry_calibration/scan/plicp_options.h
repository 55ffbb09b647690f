// Options of the point-to-line ICP matcher (PLICP), with units and defaults.
#pragma once

#include <string>

#include "odometry_calibration/scan/scan_lines.h"

namespace odometry_calibration {

/// How correspondences are searched (both exact; see nearest_point_search.h).
enum class CorrespondenceSearch
{
  kAngularOrder,  ///< walk the reference scan's rays outwards from the query's bearing (faster)
  kKdTree,  ///< PCL FLANN kd-tree over the reference points (builds with PCL only: pcl_support.h)
};

/// Options of matchScans(). Defaults suit 2D lidars of ~1 cm noise indoors with an odometry
/// initial guess a few centimetres and degrees off. Names follow Censi's CSM where one exists.
struct PlicpOptions
{
  /// A new point is matched only to a reference point within this distance [m] (CSM
  /// max_correspondence_dist).
  double max_correspondence_distance_m = 0.5;
  /// A match refused for its gate's reach is matched again from the same guess with
  /// max_correspondence_distance_m doubled, at most this many times [-], >= 0 (0: never; 2: up
  /// to 2 m, CSM's default gate, from 0.5 m). Refused for its reach: an iteration keeps fewer
  /// than min_correspondences, or it runs beyond the allowed correction, or it converges with poor
  /// overlap. A heading error of the guess moves a point by its range times the error (3 deg:
  /// 1 m at 20 m): in a scene seen mostly far away (outdoors) the far points are out of reach at
  /// the guess and the few near ones lead the match astray. Only such refusals are matched again,
  /// so no other result changes (docs/scan_matching.md, "Real scans").
  int max_correspondence_distance_doublings = 2;
  /// ... and only when the two local lines differ by less than this angle [rad] (surfaces seen
  /// from the same side; larger than the initial guess' heading error).
  double max_normal_angle_rad = 0.6;
  /// ... and only when the foot of the new point on the reference line lies within the extent
  /// of the points the line was fitted to, widened by this margin [m] (a point beyond the end of
  /// a surface belongs to something the reference scan did not see). Without a margin, small
  /// objects (legs, posts, door frames: a few centimetres of surface) constrain the match only
  /// once the pose is within their extent, so in a feature-poor corridor the match stays near
  /// its initial guess (the Mines log from a zero guess: -5.0 % of the distance without a margin,
  /// -2.4 % with 0.1 m, against -2.2 % from the odometry guess).
  double surface_extent_margin_m = 0.1;
  /// Fixed trimming: keep at most this fraction of the correspondences, the ones with the
  /// smallest point-to-line residuals [-], in (0, 1] (CSM outliers_maxPerc).
  double trim_keep_fraction = 0.95;
  /// Adaptive trimming: drop residuals larger than adaptive_trim_multiplier times the
  /// adaptive_trim_quantile-th quantile of |residual| [-] (CSM outliers_adaptive_order / _mult).
  double adaptive_trim_quantile = 0.7;
  double adaptive_trim_multiplier = 2.0;
  /// ... but never drop a residual below this [m]: keeps noise-level residuals (>= 0).
  double adaptive_trim_floor_m = 0.02;
  /// Converged when one iteration moves the pose by less than both tolerances [m], [rad]
  /// (CSM epsilon_xy, epsilon_theta).
  double translation_tolerance_m = 1e-4;
  double rotation_tolerance_rad = 1e-4;
  /// Iteration cap; reaching it without converging is a failure [iterations].
  int max_iterations = 50;
  /// The result may differ from the initial guess by at most this much, else it fails as
  /// "correction too large" [m], [rad] (CSM max_linear_correction, max_angular_correction_deg).
  double max_correction_translation_m = 0.5;
  double max_correction_rotation_rad = 0.5;
  /// Each scan needs at least this many usable points [points].
  int min_points = 20;
  /// Every iteration needs at least this many kept correspondences [correspondences].
  int min_correspondences = 20;
  /// A converged match is valid only if at least this fraction of the new scan's surface points
  /// (those with a line of their own) have a correspondence within inlier_distance_m of their
  /// line [-]: a match that converged to a wrong pose leaves most points far from any surface
  /// (real indoor scans give 0.4-0.9 when right). Points without a line (foliage, clutter) are
  /// not counted: they are off every line wherever the scan is put.
  double min_inlier_fraction = 0.3;
  double inlier_distance_m = 0.05;
  /// Standard deviation of a range reading [m], for the covariance (Censi ICRA 2007).
  double range_sigma_m = 0.01;
  /// A motion direction whose information is below this fraction of the strongest direction's
  /// is reported degenerate and held at the initial guess [-], in (0, 1).
  double min_information_ratio = 0.02;
  /// Compute the covariance (Censi ICRA 2007); without it the result's covariance is zero.
  bool compute_covariance = true;
  /// Ambiguity check of weak matches (needs the covariance): a valid match with fewer than
  /// ambiguity_max_correspondences correspondences whose weakest translation sigma exceeds
  /// ambiguity_sigma_m or whose heading sigma exceeds ambiguity_sigma_rad, or one whose
  /// information ratio (Degeneracy) is below ambiguity_max_information_ratio (near degenerate,
  /// whatever its correspondences), is matched again from four starts (the solution moved by
  /// +-ambiguity_offset_m along its weakest direction, and turned by +-ambiguity_offset_rad). A
  /// start that finds the scene degenerate with a clearly better fit (2 % more inliers) makes the
  /// match degenerate; starts that fit as well (valid, or degenerate and held where they started)
  /// but lie beyond 3 sigma widen the covariance to cover them (+ d d^T): the Censi covariance
  /// measures the noise, not which of two equally good solutions is right. Off in rich scenes (more
  /// correspondences, small sigmas), where it would cost time and find nothing. The near-degenerate
  /// test catches weak matches with many correspondences (a long wall and one pillar face: 226)
  /// without checking every match of that size (docs/scan_matching.md, "Honest in weak scenes").
  bool check_ambiguity = true;
  int ambiguity_max_correspondences = 150;
  double ambiguity_max_information_ratio = 0.04;  // twice min_information_ratio
  double ambiguity_sigma_m = 0.002;
  double ambiguity_sigma_rad = 0.001;
  double ambiguity_offset_m = 0.1;
  /// [rad], in [0, pi]; 0: the two shifted starts only, no turned ones: on the eight CARMEN logs
  /// (both seeds) no gross failure or refusal count changes, a fifth fewer matches are widened
  /// (255 of 319) and the check costs about half as much (docs/benchmarks.md, "Where Intel's
  /// time goes").
  double ambiguity_offset_rad = 0.1;
  /// A rematch stops once an iterate is within this many sigma of the solution (Mahalanobis
  /// distance under its covariance) after a step below the trimming floor
  /// (adaptive_trim_floor_m): it is taken to be going back to the solution, where it would
  /// neither widen the covariance nor replace the match (a heuristic, not a proof: measured to
  /// change no match on the ACES, FHW and Freiburg 079 logs; plicp_ambiguity.h,
  /// backAtSolution). 0: every rematch runs to convergence [-], in [0, 3).
  double ambiguity_return_sigma = 0.5;
  /// Correspondence search.
  CorrespondenceSearch correspondence_search = CorrespondenceSearch::kAngularOrder;
  /// Local line fits of both scans.
  LineFitOptions line_fit;
};

/// Throws std::invalid_argument naming the first invalid option and the valid range.
void validate(const PlicpOptions& options);

}  // namespace odometry_calibration
