#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/keyframes.h"
#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {
namespace {

using Windows = std::vector<std::pair<std::size_t, std::size_t>>;

Windows asPairs(const std::vector<KeyframeWindow>& windows)
{
  Windows pairs;
  for (const KeyframeWindow& window : windows)
    pairs.emplace_back(window.first, window.last);
  return pairs;
}

TEST(KeyframesTest, RegularStampsGiveRegularWindows)
{
  const std::vector<double> stamps{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  // Sample 10 (1.0 s) is only 0.1 s after keyframe 9, so it opens no fourth window.
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.3)), (Windows{{0, 3}, {3, 6}, {6, 9}}));
}

TEST(KeyframesTest, ComputedGridStampsAreNotShiftedByRounding)
{
  std::vector<double> stamps;
  for (int i = 0; i <= 10; ++i)
    stamps.push_back(i * 0.1);  // 0.9 - 0.6 < 0.3 in doubles
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.3)), (Windows{{0, 3}, {3, 6}, {6, 9}}));
}

TEST(KeyframesTest, JitteredStampsPickFirstSampleAtLeastIntervalLater)
{
  const std::vector<double> stamps{0.0, 0.12, 0.29, 0.31, 0.55, 0.62};
  // 0.29 is too early, 0.31 is the first keyframe after 0; then 0.55 - 0.31 = 0.24 is
  // too early and 0.62 - 0.31 = 0.31 qualifies.
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.3)), (Windows{{0, 3}, {3, 5}}));
}

TEST(KeyframesTest, SampleExactlyOneIntervalLaterIsAKeyframe)
{
  const std::vector<double> stamps{0.0, 0.25, 0.5, 0.75, 1.0};
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.5)), (Windows{{0, 2}, {2, 4}}));
}

TEST(KeyframesTest, GapLongerThanIntervalGivesOneWindow)
{
  const std::vector<double> stamps{0.0, 0.1, 2.0, 2.1, 2.2};
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.3)), (Windows{{0, 2}}));
}

TEST(KeyframesTest, EmptyInputGivesNoWindows)
{
  EXPECT_TRUE(selectKeyframeWindows({}, 0.3).empty());
}

TEST(KeyframesTest, SingleStampGivesNoWindow)
{
  EXPECT_TRUE(selectKeyframeWindows({4.2}, 0.3).empty());
}

TEST(KeyframesTest, InvalidIntervalThrows)
{
  const std::vector<double> stamps{0.0, 1.0};
  EXPECT_THROW(selectKeyframeWindows(stamps, 0.0), std::invalid_argument);
  EXPECT_THROW(selectKeyframeWindows(stamps, -0.3), std::invalid_argument);
  EXPECT_THROW(selectKeyframeWindows(stamps, std::nan("")), std::invalid_argument);
  EXPECT_THROW(selectKeyframeWindows(stamps, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
  // Checked even when there is nothing to select from.
  EXPECT_THROW(selectKeyframeWindows({}, 0.0), std::invalid_argument);
}

TEST(KeyframesTest, DecreasingStampsThrowNamingTheSample)
{
  const std::vector<double> stamps{0.0, 0.1, 0.2, 0.15, 0.4};
  try {
    selectKeyframeWindows(stamps, 0.3);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("sample 3"), std::string::npos) << error.what();
  }
}

TEST(KeyframesTest, NanStampThrows)
{
  const std::vector<double> stamps{0.0, 0.1, std::nan(""), 0.5};
  EXPECT_THROW(selectKeyframeWindows(stamps, 0.3), std::invalid_argument);
}

TEST(KeyframesTest, EqualConsecutiveStampsAreAllowed)
{
  const std::vector<double> stamps{0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75};
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.3)), (Windows{{0, 4}}));
  EXPECT_EQ(asPairs(selectKeyframeWindows(stamps, 0.25)), (Windows{{0, 2}, {2, 4}, {4, 6}}));
}

}  // namespace
}  // namespace odometry_calibration
