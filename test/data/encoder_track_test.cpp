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
  constexpr auto kLinear = EncoderInterpolation::kLinear;
  EXPECT_NEAR(t.at(1.05, kLinear).values(0), 100.0, 1e-9);
  EXPECT_NEAR(t.at(1.15, kLinear).values(0), 300.0, 1e-6);
  EXPECT_NEAR(t.at(1.15, kLinear).values(1), 50.0, 1e-6);  // halfway from 200 to -100
  // The cubic (the default) through the same readings: the wheel at a constant 2000 ticks/s is
  // the line; halfway p = (v0 + v1) / 2 + h (m0 - m1) / 8 for the steering, with the centred
  // slope at 1.1 s (-200 over 0.2 s) and the chord at the last reading (-300 over 0.1 s).
  EXPECT_NEAR(t.at(1.05).values(0), 100.0, 1e-6);
  EXPECT_NEAR(t.at(1.15).values(0), 300.0, 1e-6);
  EXPECT_NEAR(t.at(1.15).values(1), 50.0 + 0.1 * (-1000.0 + 3000.0) / 8.0, 1e-6);
  const auto window = t.between(1.05, 1.15, kLinear);
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
  const auto linear = t.between(1.03, 1.17, EncoderInterpolation::kLinear);
  EXPECT_NEAR(linear.front().values(0), 60.0, 1e-9);
  EXPECT_NEAR(linear.back().values(0), 270.0, 1e-9);
}

EncoderTrack wheelTrack(const std::vector<std::pair<double, double>>& readings)
{
  EncoderTrack t({{"wheel", EncoderKind::kIncremental, 0.0, 0.0}}, 10.0);
  for (const auto& [stamp_s, ticks] : readings)
    t.add(stamp_s, Eigen::VectorXd::Constant(1, ticks));
  return t;
}

TEST(EncoderTrack, CubicFollowsAnAcceleratingWheelBetweenSlowReadings)
{
  // A wheel at 1000 t^2 ticks read every 0.25 s: the centred slopes are its exact speeds, and
  // the cubic through them is the parabola; the chord is 15 ticks off at 0.6 s.
  std::vector<std::pair<double, double>> readings;
  for (int k = 0; k <= 4; ++k)
    readings.emplace_back(0.25 * k, 1000.0 * 0.0625 * k * k);
  const EncoderTrack t = wheelTrack(readings);
  EXPECT_NEAR(t.at(0.6).values(0), 360.0, 1e-9);
  EXPECT_NEAR(t.at(0.6, EncoderInterpolation::kLinear).values(0), 375.0, 1e-9);
  const auto window = t.between(0.3, 0.6);
  ASSERT_EQ(window.size(), 3u);
  EXPECT_NEAR(window.front().values(0), 90.0, 1e-9);
  EXPECT_NEAR(window.back().values(0) - window.front().values(0), 270.0, 1e-9);
}

TEST(EncoderTrack, CubicInventsNoMotionAtRestOrAcrossGaps)
{
  // The wheel stops at 2 s: between equal readings it stays put (no overshoot), and the
  // interval before the stop stays between its readings.
  const EncoderTrack stopping = wheelTrack({{0, 0}, {1, 100}, {2, 200}, {3, 200}, {4, 200}});
  EXPECT_EQ(stopping.at(2.5).values(0), 200.0);
  const double before_stop = stopping.at(1.5).values(0);
  EXPECT_GT(before_stop, 150.0);  // still decelerating from 100 ticks/s
  EXPECT_LT(before_stop, 200.0);
  // A reading beyond a gap (more than twice the interval away) does not shape the slope: the
  // interval's end takes the chord, as does a centred slope beyond three chords (limited).
  const EncoderTrack gap = wheelTrack({{0.0, 0}, {0.1, 10}, {0.2, 20}, {1.0, 1000}});
  EXPECT_NEAR(gap.at(0.15).values(0), 15.0, 1e-9);
  const EncoderTrack jump = wheelTrack({{0.0, 0}, {0.1, 1}, {0.2, 2}, {0.3, 100}});
  const double slope_limited = jump.at(0.15).values(0);
  EXPECT_GE(slope_limited, 1.0);
  EXPECT_LE(slope_limited, 2.0);
  EXPECT_NEAR(slope_limited, 1.5 + 0.1 * (10.0 - 30.0) / 8.0, 1e-9);
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
