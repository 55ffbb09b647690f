// Lets the data choose the keyframe interval T the pairs of a fit span, by time-blocked
// cross-validation on one yardstick: the training drive is cut into contiguous time blocks; for
// each candidate T and block, the configured model is fitted to the pairs at T that lie entirely
// outside the block and scored on the block's evaluation pairs (pairs at one fixed interval, the
// same for every candidate). The score follows the pose source (fitIntervalCriterion): a source of
// relative displacements (scan matching) by the RPE of the chained predictions (paper eq. 10), a
// source of absolute poses in a global frame (a tracker) by their ATE (eq. 11). Short pairs carry
// the source's noise and the stamps' jitter in a large part of each displacement; long ones the
// model's drift within a pair (the GP paper calls the choice "not trivial" and sets it by hand
// per robot). The score is what a user wants: odometry on data the fit never saw. The live node,
// calibrate_bag and calibrate_tricycle all choose with this one function.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// What a fold's fit is scored by on its block's evaluation pairs (metrics.h's chained score).
enum class FitIntervalCriterion
{
  kRpe,  ///< the RPE of the chained predictions (paper eq. 10)
  kAte,  ///< the ATE of the chained predictions against the chained measurements (eq. 11)
};

/// The criterion of a pose source: absolute poses in a global frame (`pose`: a tracker) are
/// scored by the ATE, relative displacements (`scan`, `cloud`: scan matching; `odometry`) by the
/// RPE. docs/results.md measures both on both kinds.
FitIntervalCriterion fitIntervalCriterion(EgoMotionSource source);

/// "RPE" or "ATE".
const char* criterionName(FitIntervalCriterion criterion);

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
  /// candidate's score is the mean over all blocks of all cuts of the block's score.
  std::vector<std::size_t> fold_counts = {3, 4};
  /// Blocks holding fewer evaluation pairs than this are not scored.
  std::size_t min_block_pairs = 4;
};

/// One point of the validation curve.
struct FitIntervalScore
{
  double interval_s = 0.0;  ///< candidate T [s]
  /// Mean over the scored blocks of the criterion's error of the evaluation pairs [m]; inf when
  /// a fold could not be fitted (too few pairs outside a block, or the fit threw).
  double validation_error_m = 0.0;
  std::size_t pairs = 0;   ///< the candidate's pairs in the training drive
  std::size_t blocks = 0;  ///< blocks scored
};

/// The choice and the curve it was made from.
struct FitIntervalChoice
{
  double interval_s = 0.0;              ///< the candidate with the lowest validation error [s]
  std::vector<FitIntervalScore> curve;  ///< one score per candidate, in the candidates' order
  FitIntervalCriterion criterion = FitIntervalCriterion::kRpe;  ///< what the curve measures
  std::vector<std::size_t> fold_counts;  ///< the cuts into time blocks the curve averages over
};

/// Cross-validates `candidates` for config.model (config.models; global yaw starts reduced to
/// one, as in the time-offset search) against `evaluation` pairs from the same drive, each block
/// scored by `criterion`. All pairs must be cut at the same time offset. Ties go to the earlier
/// candidate. Throws
/// std::invalid_argument for no candidate, invalid options, a drive too short for the folds, or
/// when no candidate can be scored.
FitIntervalChoice chooseFitInterval(const CalibrationConfig& config,
                                    const std::vector<IntervalPairs>& candidates,
                                    const std::vector<MotionPair>& evaluation,
                                    FitIntervalCriterion criterion,
                                    const FitIntervalOptions& options = {});

/// The pairs of `pairs` that end by `border_stamp_s` (the training part before a held-out
/// border; the held-out pairs are those of the evaluation interval after it).
std::vector<MotionPair> pairsEndingBy(const std::vector<MotionPair>& pairs, double border_stamp_s);

/// The pairs of `pairs` that start at or after `border_stamp_s` (the held-out part after the
/// border).
std::vector<MotionPair> pairsStartingFrom(const std::vector<MotionPair>& pairs,
                                          double border_stamp_s);

/// The curve in words, one line: "fit interval T = 0.50 s, chosen by time-blocked
/// cross-validation (validation RPE of 0.50 s pairs): 0.30 s 0.00410 m, 0.50 s 0.00370 m
/// (chosen), ...".
std::string formatFitIntervalChoice(const FitIntervalChoice& choice, double evaluation_interval_s);

}  // namespace odometry_calibration
