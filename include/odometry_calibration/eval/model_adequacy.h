// Whether a fitted model fits the robot at all: residuals that trend with the motion (curvature,
// speed, turning direction) mean the model's kinematics miss an effect (a tracked base whose
// effective wheel separation grows in tight turns, wheels that slip more at speed), which no
// parameter value can absorb; a model-free model may then generalize better.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// One trend of the relative residuals with a feature of the motion.
struct ResidualTrend
{
  std::string feature;  ///< "curvature", "speed" or "turning direction"
  /// The change of the relative error across the feature's range (10th to 90th percentile; for
  /// the turning direction: left minus right), a fraction (0.05: 5 % of the turn or distance).
  double size = 0.0;
  double t_statistic = 0.0;     ///< the change over its standard error
  double from = 0.0, to = 0.0;  ///< the feature's range [1/m for curvature, m/s for speed]
  bool significant = false;     ///< |t| and |size| beyond the check's thresholds
  std::string text;             ///< in words
};

struct AdequacyCheck
{
  std::vector<ResidualTrend> trends;  ///< every feature tested (those with enough pairs)
  bool fits = true;                   ///< no significant trend
  std::string text;  ///< "the model does not fit this robot: ..." or that no trend was found
};

/// Thresholds of the check.
struct AdequacyOptions
{
  double min_turn_rad = 0.05;         ///< pairs turning less do not enter the heading tests [rad]
  double min_distance_m = 0.05;       ///< pairs moving less do not enter the speed test [m]
  double min_abs_t = 5.0;             ///< a trend needs |t| above this ...
  double min_relative_size = 0.03;    ///< ... and a change of more than this fraction
  double max_curvature_per_m = 20.0;  ///< curvature |theta|/distance capped here (spins) [1/m]
  std::size_t min_pairs = 20;         ///< a feature with fewer usable pairs is not tested
};

/// Tests the model's relative residuals over `pairs` (its predictions against the measured
/// sensor motion) for three trends: the heading error (theta_pred - theta)/theta against the
/// measured curvature |theta|/distance (least squares line, t of its slope), the along-track
/// error (d_pred - d)/d against the speed d/T, and the heading error's mean on left against
/// right turns (Welch's t). Each relative error is clipped to +-0.5 (a bad scan match moves a
/// trend no more than a pair missed by half).
AdequacyCheck checkModelAdequacy(const MotionModel& model, const std::vector<MotionPair>& pairs,
                                 const AdequacyOptions& options = {});

/// What to use when `check` says the model does not fit: the row with the lowest ATE in
/// `scores` (a comparison on pairs not fitted, named by `where`) when it is another model,
/// else that none of the compared models does better; without scores, how to get them. Empty
/// when the model fits.
std::string adequacyAdvice(const AdequacyCheck& check, const std::string& model,
                           const std::vector<ModelScore>& scores, const std::string& where);

}  // namespace odometry_calibration
