#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/wheel_sample_alignment.h"

namespace odometry_calibration {
namespace {

/// Left wheel: 100 ticks/s + 30 ticks/s^2 * t; right: 80 ticks/s - 10 ticks/s^2 * t.
double left(double t)
{
  return 100.0 * t + 15.0 * t * t;
}
double right(double t)
{
  return 80.0 * t - 5.0 * t * t;
}

TEST(WheelSampleAligner, TheSecondWheel7MsLaterIsInterpolatedAtTheFirstWheelsInstants)
{
  WheelSampleAligner aligner(2, 0.5);
  std::vector<EncoderSample> joint;
  for (int k = 0; k < 50; ++k) {
    const double t = 0.03125 * k;  // 32 Hz
    for (const auto& s : aligner.add(0, t, left(t)))
      joint.push_back(s);
    for (const auto& s : aligner.add(1, t + 0.007, right(t + 0.007)))
      joint.push_back(s);
  }
  // Every left instant from the second on (the first precedes the right wheel's first sample).
  ASSERT_EQ(joint.size(), 49u);
  EXPECT_EQ(aligner.droppedInstants(), 1u);
  for (std::size_t i = 0; i < joint.size(); ++i) {
    const double t = 0.03125 * static_cast<double>(i + 1);
    EXPECT_DOUBLE_EQ(joint[i].stamp_s, t);
    EXPECT_DOUBLE_EQ(joint[i].values(0), left(t));
    // Linear interpolation of a parabola: error (t - a)(b - t) * 5 ticks/s^2 at most.
    const double a = t - 0.03125 + 0.007, b = t + 0.007;
    EXPECT_NEAR(joint[i].values(1), right(t), 5.0 * (t - a) * (b - t) + 1e-12) << i;
    EXPECT_GT(std::abs(joint[i].values(1) - right(t + 0.007)), 0.3);  // not the nearest sample
  }
}

TEST(WheelSampleAligner, AnInstantIsCompleteOnlyOnceTheOtherWheelHasASampleAfterIt)
{
  WheelSampleAligner aligner(2, 0.5);
  EXPECT_TRUE(aligner.add(1, 0.0, 0.0).empty());
  EXPECT_TRUE(aligner.add(0, 0.01, 5.0).empty());  // waits for the right wheel
  EXPECT_TRUE(aligner.add(0, 0.03, 15.0).empty());
  const auto out = aligner.add(1, 0.04, 40.0);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].values(1), 10.0);
  EXPECT_DOUBLE_EQ(out[1].values(1), 30.0);
}

TEST(WheelSampleAligner, ASilentWheelLeavesAGapInsteadOfAGuess)
{
  WheelSampleAligner aligner(2, 0.1);
  aligner.add(1, 0.0, 0.0);
  aligner.add(0, 0.0, 0.0);
  EXPECT_EQ(aligner.add(0, 0.05, 1.0).size(), 0u);
  EXPECT_EQ(aligner.add(0, 0.2, 2.0).size(), 0u);
  // The right wheel's next sample comes 0.3 s later: both instants inside are dropped.
  EXPECT_TRUE(aligner.add(1, 0.3, 3.0).empty());
  EXPECT_EQ(aligner.droppedInstants(), 2u);
}

TEST(WheelSampleAligner, TimeGoingBackwardsRestartsAndSaysSo)
{
  WheelSampleAligner aligner(2, 0.5);
  aligner.add(0, 1.0, 0.0);
  try {
    aligner.add(0, 0.5, 0.0);
    FAIL() << "no refusal";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("went back by 0.5"), std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(aligner.add(0, 0.5, 0.0).empty());  // accepted after the restart
  EXPECT_THROW(aligner.add(2, 0.6, 0.0), std::invalid_argument);
  EXPECT_THROW(aligner.add(1, std::nan(""), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
