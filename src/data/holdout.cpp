#include "odometry_calibration/data/holdout.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace odometry_calibration {

std::size_t holdoutStart(std::size_t count, double holdout_fraction)
{
  if (!(holdout_fraction > 0.0 && holdout_fraction < 1.0)) {
    throw std::invalid_argument("the held-out fraction must be in (0, 1), got " +
                                std::to_string(holdout_fraction));
  }
  const auto start =
      static_cast<std::size_t>(std::llround(static_cast<double>(count) * (1.0 - holdout_fraction)));
  if (start < 2 || count < start + 2) {
    throw std::invalid_argument("holding out " + std::to_string(holdout_fraction) + " of " +
                                std::to_string(count) +
                                " samples leaves fewer than two samples on one side");
  }
  return start;
}

std::vector<SampleBlock> timeBlocks(const std::vector<double>& stamps_s, std::size_t block_count)
{
  if (block_count < 1) {
    throw std::invalid_argument("time blocks: at least one block is needed");
  }
  if (stamps_s.size() < 2 * block_count) {
    throw std::invalid_argument("time blocks: " + std::to_string(stamps_s.size()) +
                                " samples cannot make " + std::to_string(block_count) +
                                " blocks of at least two samples");
  }
  const double start_s = stamps_s.front();
  const double duration_s = (stamps_s.back() - start_s) / static_cast<double>(block_count);
  std::vector<SampleBlock> blocks;
  std::size_t first = 0;
  for (std::size_t k = 0; k < block_count; ++k) {
    std::size_t end = stamps_s.size();  // one past the block's last sample
    if (k + 1 < block_count) {
      const double end_s = start_s + duration_s * static_cast<double>(k + 1);
      end = first;
      while (end < stamps_s.size() && stamps_s[end] < end_s) {
        ++end;
      }
    }
    if (end < first + 2) {
      throw std::invalid_argument("time blocks: block " + std::to_string(k) +
                                  " holds fewer than two samples (a gap in the log?)");
    }
    blocks.push_back({first, end - 1});
    first = end;
  }
  return blocks;
}

PairHoldout holdOutLastPairs(const std::vector<MotionPair>& pairs, double holdout_fraction)
{
  if (!(holdout_fraction > 0.0 && holdout_fraction < 1.0)) {
    throw std::invalid_argument("the held-out fraction must be in (0, 1), got " +
                                std::to_string(holdout_fraction));
  }
  PairHoldout split;
  if (pairs.empty()) {
    throw std::invalid_argument("no pair to hold out");
  }
  const double start_s = pairs.front().start_stamp_s;
  const double end_s = pairs.back().end_stamp_s;
  split.border_stamp_s = start_s + (1.0 - holdout_fraction) * (end_s - start_s);
  for (const MotionPair& pair : pairs) {
    if (pair.end_stamp_s <= split.border_stamp_s) {
      split.training.push_back(pair);
    } else if (pair.start_stamp_s >= split.border_stamp_s) {
      split.test.push_back(pair);
    }
  }
  if (split.training.size() < 2 || split.test.size() < 2) {
    throw std::invalid_argument("holding out " + std::to_string(holdout_fraction) + " of " +
                                std::to_string(pairs.size()) +
                                " pairs leaves fewer than two pairs on one side");
  }
  return split;
}

}  // namespace odometry_calibration
