#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/holdout.h"

namespace odometry_calibration {
namespace {

TEST(Holdout, HoldsOutTheLastFractionInTime)
{
  EXPECT_EQ(holdoutStart(10, 0.4), 6u);  // samples 0-5 train, 6-9 test
  EXPECT_EQ(holdoutStart(2434, 0.4), 1460u);
  EXPECT_EQ(holdoutStart(2434, 0.5), 1217u);
  EXPECT_EQ(holdoutStart(2434, 0.2), 1947u);
  EXPECT_EQ(holdoutStart(4, 0.5), 2u);
}

TEST(Holdout, RefusesFractionsThatLeaveASideEmpty)
{
  EXPECT_THROW(holdoutStart(10, 0.0), std::invalid_argument);
  EXPECT_THROW(holdoutStart(10, 1.0), std::invalid_argument);
  EXPECT_THROW(holdoutStart(10, -0.1), std::invalid_argument);
  EXPECT_THROW(holdoutStart(10, 0.95), std::invalid_argument);  // one training sample
  EXPECT_THROW(holdoutStart(10, 0.05), std::invalid_argument);  // no test sample
  EXPECT_THROW(holdoutStart(3, 0.5), std::invalid_argument);
}

TEST(Holdout, TimeBlocksAreContiguousAndOfEqualDuration)
{
  std::vector<double> stamps;
  for (int i = 0; i < 100; ++i)
    stamps.push_back(10.0 + 0.5 * i);  // 49.5 s
  const std::vector<SampleBlock> blocks = timeBlocks(stamps, 4);
  ASSERT_EQ(blocks.size(), 4u);
  // Borders at 10 + k * 12.375 s: samples 25, 50, 75 open the next blocks.
  EXPECT_EQ(blocks[0].first, 0u);
  EXPECT_EQ(blocks[0].last, 24u);
  EXPECT_EQ(blocks[1].first, 25u);
  EXPECT_EQ(blocks[1].last, 49u);
  EXPECT_EQ(blocks[2].first, 50u);
  EXPECT_EQ(blocks[2].last, 74u);
  EXPECT_EQ(blocks[3].first, 75u);
  EXPECT_EQ(blocks[3].last, 99u);

  // Uneven sampling: blocks follow time, not sample counts.
  const std::vector<double> uneven = {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 1.0, 2.0};
  const std::vector<SampleBlock> halves = timeBlocks(uneven, 2);
  EXPECT_EQ(halves[0].last, 5u);
  EXPECT_EQ(halves[1].first, 6u);
  EXPECT_EQ(halves[1].last, 7u);
}

TEST(Holdout, TimeBlocksRefuseBlocksOfFewerThanTwoSamples)
{
  EXPECT_THROW(timeBlocks({0.0, 1.0, 2.0}, 2), std::invalid_argument);
  EXPECT_THROW(timeBlocks({0.0, 1.0}, 0), std::invalid_argument);
  // A gap leaves the middle block empty.
  EXPECT_THROW(timeBlocks({0.0, 0.1, 0.2, 0.3, 9.7, 9.8, 9.9, 10.0}, 3), std::invalid_argument);
}

TEST(Holdout, PairsAreSplitByTimeAndTheOneAcrossTheBorderIsDropped)
{
  std::vector<MotionPair> pairs;
  for (int i = 0; i < 10; ++i) {  // [0, 1], [1, 2], ... [9, 10] s
    MotionPair pair;
    pair.start_stamp_s = i;
    pair.end_stamp_s = i + 1.0;
    pairs.push_back(pair);
  }
  const PairHoldout split = holdOutLastPairs(pairs, 0.35);  // border at 6.5 s
  EXPECT_DOUBLE_EQ(split.border_stamp_s, 6.5);
  ASSERT_EQ(split.training.size(), 6u);  // up to [5, 6]
  ASSERT_EQ(split.test.size(), 3u);      // from [7, 8]; [6, 7] crosses the border
  EXPECT_DOUBLE_EQ(split.training.back().end_stamp_s, 6.0);
  EXPECT_DOUBLE_EQ(split.test.front().start_stamp_s, 7.0);
  EXPECT_EQ(holdOutLastPairs(pairs, 0.4).training.size(), 6u);  // [5, 6] ends on the border
  EXPECT_THROW(holdOutLastPairs(pairs, 0.05), std::invalid_argument);
  EXPECT_THROW(holdOutLastPairs(pairs, 1.0), std::invalid_argument);
  EXPECT_THROW(holdOutLastPairs({}, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
