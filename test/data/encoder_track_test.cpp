#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/encoder_track.h"

namespace odometry_calibration {
namespace {

EncoderTrack track()
{
  return EncoderTrack({{"wheel", EncoderKind::kIncremental, 4294967296.0, 0.0},
                       {"steering", EncoderKind::kAbsolute, 0.0, 8192.0}},
                      10.0);
}

TEST(EncoderTrack, InterpolatesBetweenSamplesAcrossAWrap)
{
  EncoderTrack t = track();
  t.add(1.0, Eigen::Vector2d(4294967000.0, 100));
  t.add(1.1, Eigen::Vector2d(4294967200.0, 200));
  t.add(1.2, Eigen::Vector2d(104.0, 8092));  // wrapped: +200 ticks; steering -100
  EXPECT_NEAR(t.at(1.05).values(0), 100.0, 1e-9);
  EXPECT_NEAR(t.at(1.15).values(0), 300.0, 1e-6);
  EXPECT_NEAR(t.at(1.15).values(1), 50.0, 1e-6);  // halfway from 200 to -100
  const auto window = t.between(1.05, 1.15);
  ASSERT_EQ(window.size(), 3u);
  EXPECT_NEAR(window.front().stamp_s, 1.05, 1e-12);
  EXPECT_NEAR(window[1].values(0), 200.0, 1e-9);
  EXPECT_NEAR(window.back().values(0), 300.0, 1e-6);
  EXPECT_THROW(t.at(1.3), std::out_of_range);
  EXPECT_THROW(t.between(0.9, 1.1), std::out_of_range);
}

TEST(EncoderTrack, NearestReadingInsteadOfInterpolation)
{
  EncoderTrack t = track();
  t.add(1.0, Eigen::Vector2d(1000, 100));
  t.add(1.1, Eigen::Vector2d(1200, 200));
  t.add(1.2, Eigen::Vector2d(1300, 300));
  const auto window = t.between(1.03, 1.17, EncoderInterpolation::kNearest);
  ASSERT_EQ(window.size(), 3u);
  EXPECT_NEAR(window.front().stamp_s, 1.03, 1e-12);  // stamped where asked
  EXPECT_EQ(window.front().values(0), 0.0);          // the reading at 1.0 (counts from it)
  EXPECT_EQ(window[1].values(0), 200.0);
  EXPECT_NEAR(window.back().stamp_s, 1.17, 1e-12);
  EXPECT_EQ(window.back().values(0), 300.0);  // the reading at 1.2
  EXPECT_EQ(window.back().values(1), 300.0);
  // Linear for comparison: 30 % and 70 % of the way.
  const auto linear = t.between(1.03, 1.17);
  EXPECT_NEAR(linear.front().values(0), 60.0, 1e-9);
  EXPECT_NEAR(linear.back().values(0), 270.0, 1e-9);
}

TEST(EncoderTrack, TimeGoingBackwardsRestartsTheTrack)
{
  EncoderTrack t = track();
  t.add(5.0, Eigen::Vector2d(1000, 0));
  t.add(5.1, Eigen::Vector2d(1100, 0));
  EXPECT_EQ(t.add(5.1, Eigen::Vector2d(1100, 0)), EncoderTrack::AddResult::kDuplicate);
  EXPECT_EQ(t.add(1.0, Eigen::Vector2d(1000, 0)), EncoderTrack::AddResult::kRestarted);
  EXPECT_EQ(t.firstStamp(), 1.0);
  EXPECT_EQ(t.at(1.0).values(0), 0.0);  // counts start again
  t.add(1.1, Eigen::Vector2d(1050, 0));
  EXPECT_EQ(t.at(1.1).values(0), 50.0);
}

TEST(EncoderTrack, GapsAndHistory)
{
  EncoderTrack t = track();
  t.add(0.0, Eigen::Vector2d(0, 0));
  t.add(0.1, Eigen::Vector2d(10, 0));
  t.add(2.0, Eigen::Vector2d(200, 0));  // a silent encoder for 1.9 s
  EXPECT_TRUE(t.covers(0.05, 0.5));
  EXPECT_FALSE(t.covers(1.0, 0.5));
  EXPECT_NEAR(t.largestGap(0.0, 2.0), 1.9, 1e-12);
  for (int k = 1; k <= 200; ++k)
    t.add(2.0 + 0.1 * k, Eigen::Vector2d(200 + k, 0));
  EXPECT_GE(t.firstStamp(), 22.0 - 10.0 - 0.1 - 1e-9);  // older than 10 s dropped
}

TEST(EncoderTrack, LargestGapIsTheLargestGapTouchingTheInterval)
{
  // Irregular stamps: gaps of 0.02 s, one of 0.3 s after 1.0 s and one of 0.7 s after 3.0 s.
  EncoderTrack t = track();
  std::vector<double> stamps;
  for (double stamp = 0.0; stamp < 5.0;) {
    stamps.push_back(stamp);
    t.add(stamp, Eigen::Vector2d(stamps.size(), 0));
    stamp += std::abs(stamp - 1.0) < 1e-9 ? 0.3 : std::abs(stamp - 3.0) < 1e-9 ? 0.7 : 0.02;
    stamp = std::round(stamp * 100.0) / 100.0;
  }
  // Every gap with its later sample at or after the start and its earlier one at or before
  // the end counts (a gap straddling either end too).
  auto expected = [&](double start_s, double end_s) {
    double largest = 0.0;
    for (std::size_t k = 1; k < stamps.size(); ++k) {
      if (stamps[k] >= start_s && stamps[k - 1] <= end_s)
        largest = std::max(largest, stamps[k] - stamps[k - 1]);
    }
    return largest;
  };
  for (const auto& [start_s, end_s] : std::vector<std::pair<double, double>>{{0.0, 0.5},
                                                                             {0.9, 1.1},
                                                                             {1.1, 1.2},
                                                                             {1.3, 1.3},
                                                                             {1.31, 2.9},
                                                                             {2.95, 3.0},
                                                                             {3.0, 3.0},
                                                                             {3.5, 3.6},
                                                                             {3.71, 5.0},
                                                                             {-1.0, 9.0},
                                                                             {4.99, 9.0},
                                                                             {6.0, 7.0}}) {
    EXPECT_EQ(t.largestGap(start_s, end_s), expected(start_s, end_s)) << start_s << " " << end_s;
  }
  EXPECT_NEAR(t.largestGap(1.1, 1.2), 0.3, 1e-12);   // inside the 0.3 s gap
  EXPECT_NEAR(t.largestGap(2.95, 3.0), 0.7, 1e-12);  // ends at the sample before the gap
  EXPECT_NEAR(t.largestGap(3.71, 3.8), 0.02, 1e-12);
  EXPECT_EQ(t.largestGap(6.0, 7.0), 0.0);  // after the last sample
}

TEST(EncoderTrack, BadReadingsLeaveTheTrackUnchanged)
{
  EncoderTrack t = track();
  t.add(0.0, Eigen::Vector2d(0, 0));
  EXPECT_THROW(t.add(0.1, Eigen::Vector3d(1, 2, 3)), std::invalid_argument);
  EXPECT_THROW(t.add(0.1, Eigen::Vector2d(std::nan(""), 0)), std::invalid_argument);
  EXPECT_EQ(t.lastStamp(), 0.0);
  t.add(0.1, Eigen::Vector2d(7, 0));
  EXPECT_EQ(t.at(0.1).values(0), 7.0);
}

}  // namespace
}  // namespace odometry_calibration
