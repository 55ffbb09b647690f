// Evaluation of a tricycle calibration against the ego-motion reference, and the text report.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// Trajectory errors of the dead-reckoned sensor trajectory against the reference, for the
/// initial (nominal) and the calibrated parameters.
struct TricycleEvaluation
{
  double ate_initial_m = 0.0;     ///< paper eq. 11, nominal parameters [m]
  double ate_calibrated_m = 0.0;  ///< paper eq. 11, calibrated parameters [m]
  double rpe_initial_m = 0.0;     ///< paper eq. 10 between keyframes, nominal [m]
  double rpe_calibrated_m = 0.0;  ///< paper eq. 10 between keyframes, calibrated [m]
  std::size_t pose_count = 0;     ///< poses compared for the ATE
  double duration_s = 0.0;        ///< time spanned by the trajectory [s]
};

/// Dead-reckons the sensor from the first reference pose through all `samples` with both
/// parameter sets and compares with `reference` (one pose per sample): ATE over all samples,
/// RPE between the samples at `keyframe_indices`.
TricycleEvaluation evaluateTricycle(const TricycleCalibrationResult& result,
                                    const TricycleEncoderLayout& layout,
                                    const std::vector<EncoderSample>& samples,
                                    const std::vector<Pose2>& reference,
                                    const std::vector<std::size_t>& keyframe_indices);

/// Human-readable report: parameters with sigma, residuals before/after, inliers/outliers,
/// solver summary, trajectory errors, warnings.
std::string formatTricycleReport(const TricycleCalibrationResult& result,
                                 const TricycleEvaluation& evaluation);

/// One point of the validation curve of the keyframe interval.
struct IntervalScore
{
  double interval_s = 0.0;  ///< candidate T [s]
  /// Mean over the blocks of all cuts of the ATE of the block's chained evaluation pairs [m];
  /// inf: a fold could not be fitted (too few pairs outside it).
  double validation_ate_m = 0.0;
  std::size_t pairs = 0;  ///< pairs at this T in the fitted samples
};

/// How the keyframe interval was set and how the fit did on data it never saw.
struct TricycleValidation
{
  double interval_s = 0.0;               ///< the keyframe interval T of the fit [s]
  bool interval_chosen = false;          ///< T chosen by cross-validation (else set by hand)
  std::vector<std::size_t> fold_counts;  ///< cuts (numbers of time blocks) of the validation
  double evaluation_interval_s = 0.0;    ///< the interval of the blocks' evaluation pairs [s]
  std::vector<IntervalScore> curve;
  /// Why the interval could not be chosen (and a fixed one was used); "" otherwise.
  std::string fallback_reason;       ///< the validation curve (interval_chosen)
  double holdout_fraction = 0.0;     ///< last part of the log held out (0: none)
  std::size_t training_samples = 0;  ///< samples the fit saw (the first ones)
  std::size_t held_out_samples = 0;  ///< samples after them, never seen by the fit
  TricycleEvaluation held_out;       ///< errors on the held-out samples (holdout_fraction > 0)
};

/// Report text: the interval (with the validation curve when chosen) and the held-out errors.
std::string formatTricycleValidation(const TricycleValidation& validation);

}  // namespace odometry_calibration
