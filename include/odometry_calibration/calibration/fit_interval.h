// Lets the data choose the keyframe interval T the laser pairs of a fit span, by
// time-blocked cross-validation on one yardstick: the training drive is cut into contiguous
// time blocks; for each candidate T and block, the configured model is fitted to the pairs at T
// that lie entirely outside the block and scored on the block's evaluation pairs (pairs at one
// fixed interval, the same for every candidate), by the RPE of their chained predictions (paper
// eq. 10). Short pairs carry the matcher's noise and the stamps' jitter in a large part of each
// displacement; long ones the model's drift within a pair (the GP paper calls the choice "not
// trivial" and sets it by hand per robot). The score is what a user wants: odometry over windows
// of a fixed length on data the fit never saw.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// The pairs of one candidate interval, collected from the same drive as the others.
struct IntervalPairs
{
  double interval_s = 0.0;        ///< keyframe interval T [s]
  std::vector<MotionPair> pairs;  ///< sorted by start stamp
};

/// How to cross-validate.
struct FitIntervalOptions
{
  /// The drive is cut into this many contiguous time blocks, once per entry (each >= 2); a
  /// candidate's score is the mean over all blocks of all cuts of the block's RPE.
  std::vector<std::size_t> fold_counts = {3, 4};
  /// Blocks holding fewer evaluation pairs than this are not scored.
  std::size_t min_block_pairs = 4;
};

/// One point of the validation curve.
struct FitIntervalScore
{
  double interval_s = 0.0;  ///< candidate T [s]
  /// Mean over the scored blocks of the RPE of the evaluation pairs [m]; inf when a fold could
  /// not be fitted (too few pairs outside a block, or the fit threw).
  double validation_rpe_m = 0.0;
  std::size_t pairs = 0;   ///< the candidate's pairs in the training drive
  std::size_t blocks = 0;  ///< blocks scored
};

/// The choice and the curve it was made from.
struct FitIntervalChoice
{
  double interval_s = 0.0;              ///< the candidate with the lowest validation RPE [s]
  std::vector<FitIntervalScore> curve;  ///< one score per candidate, in the candidates' order
};

/// Cross-validates `candidates` for config.model (config.models; global yaw starts reduced to
/// one, as in the time-offset search) against `evaluation` pairs from the same drive. All pairs
/// must be cut at the same time offset. Ties go to the earlier candidate. Throws
/// std::invalid_argument for no candidate, invalid options, a drive too short for the folds, or
/// when no candidate can be scored.
FitIntervalChoice chooseFitInterval(const CalibrationConfig& config,
                                    const std::vector<IntervalPairs>& candidates,
                                    const std::vector<MotionPair>& evaluation,
                                    const FitIntervalOptions& options = {});

/// The pairs of `pairs` that end by `border_stamp_s` (the training part before a held-out
/// border; the held-out pairs are those of the evaluation interval after it).
std::vector<MotionPair> pairsEndingBy(const std::vector<MotionPair>& pairs, double border_stamp_s);

/// The curve in words, one line: "fit interval T chosen by cross-validation: 0.3 s 0.0041 m,
/// 0.5 s 0.0037 m (chosen), ...".
std::string formatFitIntervalChoice(const FitIntervalChoice& choice, double evaluation_interval_s);

}  // namespace odometry_calibration
