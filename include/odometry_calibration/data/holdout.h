// Splits of a time-ordered log for honest evaluation: the last part held out for testing, and
// contiguous time blocks for cross-validation inside the training part (never random samples:
// neighbouring samples share noise and motion, so a random split would leak).
#pragma once

#include <cstddef>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// Index of the first held-out sample when the last `holdout_fraction` of `count` time-ordered
/// samples is held out: round(count * (1 - holdout_fraction)). Samples [0, index) train, samples
/// [index, count) test. Throws std::invalid_argument unless 0 < holdout_fraction < 1 and both
/// parts keep at least two samples.
std::size_t holdoutStart(std::size_t count, double holdout_fraction);

/// A contiguous range of samples [first, last] (both included).
struct SampleBlock
{
  std::size_t first = 0;
  std::size_t last = 0;
};

/// Cuts increasing `stamps_s` into `block_count` contiguous blocks of (nearly) equal duration:
/// block k holds the samples with stamp in [t0 + k D, t0 + (k+1) D), D = span / block_count (the
/// last sample goes to the last block). Throws std::invalid_argument if block_count < 1 or any
/// block would hold fewer than two samples.
std::vector<SampleBlock> timeBlocks(const std::vector<double>& stamps_s, std::size_t block_count);

/// Time-ordered pairs cut for a held-out test: with t0 the first pair's start and t1 the last
/// pair's end, the pairs that end by t0 + (1 - holdout_fraction) (t1 - t0) train, those that
/// start at or after it test, a pair across the border is dropped.
struct PairHoldout
{
  std::vector<MotionPair> training;
  std::vector<MotionPair> test;
  double border_stamp_s = 0.0;  ///< the border [s]
};

/// Splits `pairs` (sorted by start) as PairHoldout says. Throws std::invalid_argument unless
/// 0 < holdout_fraction < 1 and both parts keep at least two pairs.
PairHoldout holdOutLastPairs(const std::vector<MotionPair>& pairs, double holdout_fraction);

}  // namespace odometry_calibration
