// The median spacing of a stream's stamps, from which the encoder gap limit is derived.
#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/data/stream_spacing.h"

namespace odometry_calibration {
namespace {

TEST(StreamSpacing, IsTheMedianOfTheRecentPositiveSpacings)
{
  StreamSpacing spacing(5);
  EXPECT_TRUE(std::isnan(spacing.median_s()));
  spacing.add(10.0);
  EXPECT_TRUE(std::isnan(spacing.median_s()));  // one stamp: no spacing yet
  // Spacings 0.2, 0.3, 0.25, then a repeated stamp and one going backwards (no spacing), then
  // 0.26 measured from the stamp that went back.
  for (double stamp : {10.2, 10.5, 10.75, 10.75, 10.0, 10.26})
    spacing.add(stamp);
  EXPECT_EQ(spacing.count(), 4u);
  EXPECT_DOUBLE_EQ(spacing.median_s(), 0.26);  // of 0.2, 0.25, 0.26, 0.3: the upper middle
  // The ring keeps the last five: a run of 0.02 s spacings takes over.
  for (int i = 1; i <= 5; ++i)
    spacing.add(10.26 + 0.02 * i);
  EXPECT_EQ(spacing.count(), 5u);
  EXPECT_NEAR(spacing.median_s(), 0.02, 1e-12);
  spacing.add(std::nan(""));  // ignored
  EXPECT_NEAR(spacing.median_s(), 0.02, 1e-12);
  spacing.clear();
  EXPECT_EQ(spacing.count(), 0u);
  EXPECT_TRUE(std::isnan(spacing.median_s()));
}

}  // namespace
}  // namespace odometry_calibration
