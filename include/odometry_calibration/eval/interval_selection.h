// Lets the data choose the keyframe interval T of a tracker-based tricycle calibration, by
// time-blocked cross-validation: the drive is cut into contiguous time blocks; for each candidate
// T and each block, the model is fitted to the pairs that lie entirely outside the block and
// dead-reckoned through the block from its first reference pose; T's score is the RMS of these
// held-out ATEs (paper eq. 11), averaged over several cuts (2, 3, ... 6 blocks). Short windows are
// dominated by the reference's noise, long ones by the model's drift (the GP paper calls the choice
// of T "not trivial"); the score measures what a user wants, odometry on data the fit never saw.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// What to try and how.
struct IntervalSelectionOptions
{
  /// Candidate keyframe intervals T [s], increasing.
  std::vector<double> candidates_s = {0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0};
  /// The drive is cut into this many contiguous time blocks, once per entry (each >= 2); a
  /// candidate's score is the mean over the entries of the RMS over that cut's blocks. Several
  /// cuts average out the luck of where one cut's block borders fall (a single cut's curve is
  /// noisy on a two-minute log).
  std::vector<std::size_t> fold_counts = {2, 3, 4, 5, 6};
  /// Start a window every stride_s [s] (overlapping windows, referencePairs); 0: end to end.
  double stride_s = 0.0;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const IntervalSelectionOptions& options);

/// One point of the validation curve.
struct IntervalScore
{
  double interval_s = 0.0;  ///< candidate T [s]
  /// Mean over the cuts of the RMS over their blocks of the held-out block ATE [m]; inf: a fold
  /// could not be fitted (too few pairs outside it).
  double validation_ate_m = 0.0;
  std::size_t pairs = 0;  ///< pairs over the whole drive at this T
};

/// The choice and the curve it was made from.
struct IntervalChoice
{
  double interval_s = 0.0;           ///< the candidate with the lowest validation ATE [s]
  std::vector<IntervalScore> curve;  ///< one score per candidate, in the candidates' order
};

/// Cross-validates the candidates on `samples` with one reference sensor pose per sample, fitting
/// from `initial` with `calibration` options and `covariance` per pair [m^2, rad^2]. A candidate
/// that leaves a fold with too few pairs (or whose fit throws) scores infinity. Throws
/// std::invalid_argument for invalid options, too short a drive for the folds, or when no
/// candidate can be scored.
IntervalChoice chooseTricycleInterval(const std::vector<EncoderSample>& samples,
                                      const std::vector<Pose2>& T_world_sensor,
                                      const TricycleEncoderLayout& layout,
                                      const TricycleParameters& initial,
                                      const TricycleCalibrationOptions& calibration,
                                      const Eigen::Matrix3d& covariance,
                                      const IntervalSelectionOptions& options);

}  // namespace odometry_calibration
