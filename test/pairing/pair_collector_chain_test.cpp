// The pair collector's consecutive chain (issue 33): the scale check against it, the decimated
// scans it matches (decimated_scan.h), its failures redone with every ray, pair motions from it,
// its scans spaced in time (consecutive_min_spacing_s).
#include <atomic>
#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/pairing/decimated_scan.h"
#include "odometry_calibration/pairing/pair_collector.h"

#include "support/pair_collector_room.h"

namespace odometry_calibration {
namespace {

using test::Feeder;
using test::kRoom;
using test::nominalPredictor;
using test::roomPairs;
using test::scenario;
using test::toScan;
using test::wheels;

TEST(PairCollector, ScaleCheckComparesKeyframeMatchesWithTheChain)
{
  CollectorOptions options;
  CollectorStatistics statistics;
  const std::vector<MotionPair> pairs = roomPairs(options, &statistics);
  ASSERT_GT(pairs.size(), 20u);
  // Every verified pair that moved is compared; in the simulated room both agree closely.
  EXPECT_GE(statistics.scale_check_pairs, pairs.size() * 9 / 10);
  EXPECT_LE(statistics.scale_check_pairs, pairs.size());
  const double agreed_pct = statistics.keyframeVersusChainPercent();
  EXPECT_LT(std::abs(agreed_pct), 0.5);
  // Its standard error: positive, and the difference from 0 within three of it.
  const double error_pct = statistics.keyframeVersusChainStandardErrorPercent();
  EXPECT_GT(error_pct, 0.0);
  EXPECT_LT(std::abs(agreed_pct), 3.0 * error_pct);
  // Keyframe matches (the ones asked for a covariance) read 2 % long: the check sees 2 % more.
  options.matcher = [](const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& guess, const PlicpOptions& plicp) {
    PlicpResult result = matchScans(reference, current, guess, plicp);
    if (plicp.compute_covariance)
      result.T_ref_new =
          Pose2(1.02 * result.T_ref_new.x(), 1.02 * result.T_ref_new.y(), result.T_ref_new.theta());
    return result;
  };
  CollectorStatistics scaled;
  roomPairs(options, &scaled);
  ASSERT_GT(scaled.scale_check_pairs, 20u);
  std::printf("[ pairing ] scale check: %+.2f %%, keyframe matches 2 %% long %+.2f %%\n",
              agreed_pct, scaled.keyframeVersusChainPercent());
  EXPECT_NEAR(scaled.keyframeVersusChainPercent() - agreed_pct, 2.0, 0.3);
  // Without the consistency check there is nothing to compare.
  options = CollectorOptions();
  options.check_consistency = false;
  CollectorStatistics unchecked;
  roomPairs(options, &unchecked);
  EXPECT_EQ(unchecked.scale_check_pairs, 0u);
  EXPECT_TRUE(std::isnan(unchecked.keyframeVersusChainPercent()));
  EXPECT_TRUE(std::isnan(unchecked.keyframeVersusChainStandardErrorPercent()));
}

TEST(DecimateRays, KeepsEveryKthRayWithItsBearingReadingAndTime)
{
  Scan scan;
  scan.angle_min_rad = -1.0;
  scan.angle_increment_rad = 0.01;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.time_increment_s = 1e-4;
  for (int i = 0; i < 10; ++i) {
    scan.ranges_m.push_back(1.0 + 0.1 * i);
    scan.valid.push_back(i % 3 == 0 ? 0 : 1);
    scan.ray_times_s.push_back(2e-4 * i);
  }
  const Scan coarse = decimateRays(scan, 4);  // rays 0, 4, 8
  ASSERT_EQ(coarse.ranges_m.size(), 3u);
  EXPECT_DOUBLE_EQ(coarse.ranges_m[2], 1.8);
  EXPECT_EQ(coarse.valid, (std::vector<std::uint8_t>{0, 1, 1}));
  EXPECT_DOUBLE_EQ(coarse.ray_times_s[1], 8e-4);
  EXPECT_TRUE(coarse.ray_angles_rad.empty());
  EXPECT_DOUBLE_EQ(coarse.angle_min_rad + 2 * coarse.angle_increment_rad, -1.0 + 8 * 0.01);
  EXPECT_DOUBLE_EQ(coarse.time_increment_s, 4e-4);
  EXPECT_EQ(decimateRays(scan, 1).ranges_m, scan.ranges_m);
  EXPECT_THROW(decimateRays(scan, 0), std::invalid_argument);
}

TEST(PairCollector, ACoarseChainKeepsTheKeyframeMatchesAndRedoesItsFailuresWithEveryRay)
{
  // 682-ray scans, at most 180 rays for the chain: every 4th ray (171).
  CollectorOptions options;
  CollectorStatistics plain_statistics, coarse_statistics, fallback_statistics;
  const std::vector<MotionPair> plain = roomPairs(options, &plain_statistics);
  options.consecutive_max_rays = 180;
  std::atomic<std::size_t> largest_chain_scan{0}, smallest_keyframe_scan{1000000};
  options.matcher = [&](const PreparedScan& reference, const PreparedScan& current,
                        const Pose2& guess, const PlicpOptions& plicp) {
    const std::size_t points = std::max(reference.points.size(), current.points.size());
    if (plicp.compute_covariance) {
      smallest_keyframe_scan = std::min<std::size_t>(smallest_keyframe_scan, points);
    } else {
      largest_chain_scan = std::max<std::size_t>(largest_chain_scan, points);
    }
    return matchScans(reference, current, guess, plicp);
  };
  const std::vector<MotionPair> coarse = roomPairs(options, &coarse_statistics);
  ASSERT_GT(plain.size(), 20u);
  EXPECT_LE(largest_chain_scan, 171u);
  EXPECT_GT(smallest_keyframe_scan, 400u);
  // The keyframe matches are the same: the pairs too, as the coarse chain agrees with them.
  ASSERT_EQ(coarse.size(), plain.size());
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_EQ(coarse[k].start_stamp_s, plain[k].start_stamp_s);
    EXPECT_EQ(coarse[k].sensor_motion.x(), plain[k].sensor_motion.x());
    EXPECT_EQ(coarse[k].covariance, plain[k].covariance);
  }
  EXPECT_EQ(coarse_statistics.consecutive_matches, plain_statistics.consecutive_matches);
  EXPECT_EQ(coarse_statistics.consecutive_rematched_all_rays, 0u);
  // Every coarse match failing: each is redone with every ray, which gives the plain chain.
  options.matcher = [](const PreparedScan& reference, const PreparedScan& current,
                       const Pose2& guess, const PlicpOptions& plicp) {
    if (!plicp.compute_covariance && current.points.size() <= 171) {
      PlicpResult result;
      result.status = PlicpStatus::kNoConvergence;
      result.T_ref_new = guess;
      return result;
    }
    return matchScans(reference, current, guess, plicp);
  };
  const std::vector<MotionPair> fallback = roomPairs(options, &fallback_statistics);
  ASSERT_EQ(fallback.size(), plain.size());
  EXPECT_EQ(fallback_statistics.consecutive_failures, 0u);
  EXPECT_EQ(fallback_statistics.consecutive_rematched_all_rays,
            fallback_statistics.consecutive_matches);
  EXPECT_EQ(fallback_statistics.chained_m, plain_statistics.chained_m);
  EXPECT_EQ(fallback_statistics.scale_check_pairs, plain_statistics.scale_check_pairs);
}

/// The pairs of a 20 s run in the room with the laser at rate_hz, with `options`.
std::vector<MotionPair> roomPairsAt(double rate_hz, const CollectorOptions& options,
                                    CollectorStatistics* statistics)
{
  sim::Scenario s = scenario(20.0);
  s.laser.rate_hz = rate_hz;
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  PairCollector collector(wheels(), options, test::nominalPredictor());
  Feeder feeder;
  feeder.collector = &collector;
  sim::simulate(s, world, *robot, feeder);
  feeder.take(collector.flush());
  *statistics = collector.statistics();
  return feeder.pairs;
}

TEST(PairCollector, ASpacedChainMatchesFewerScansWhateverTheLaserRate)
{
  CollectorOptions options;
  options.consecutive_max_rays = 180;
  CollectorStatistics every_scan, spaced, spaced_40hz;
  const std::vector<MotionPair> plain = roomPairs(options, &every_scan);
  // T = 0.5 s at 10 Hz: the chain takes the keyframe, the scan 0.3 s later and the next
  // keyframe, 2 matches per interval instead of 5; the pairs (keyframe matches) are the same.
  options.consecutive_min_spacing_s = 0.25;
  const std::vector<MotionPair> fewer = roomPairs(options, &spaced);
  ASSERT_GT(plain.size(), 20u);
  ASSERT_EQ(fewer.size(), plain.size());
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_EQ(fewer[k].start_stamp_s, plain[k].start_stamp_s);
    EXPECT_EQ(fewer[k].sensor_motion.vector(), plain[k].sensor_motion.vector());
  }
  EXPECT_EQ(spaced.consecutive_failures, 0u);
  EXPECT_EQ(spaced.scale_check_pairs, every_scan.scale_check_pairs);
  EXPECT_NEAR(static_cast<double>(spaced.consecutive_matches),
              0.4 * static_cast<double>(every_scan.consecutive_matches),
              0.02 * static_cast<double>(every_scan.consecutive_matches));
  // A 40 Hz laser: as many chain matches as at 10 Hz (without the spacing, 4 times as many).
  const std::vector<MotionPair> fast = roomPairsAt(40.0, options, &spaced_40hz);
  ASSERT_GT(fast.size(), 20u);
  EXPECT_NEAR(static_cast<double>(spaced_40hz.scans), 4.0 * static_cast<double>(spaced.scans), 4.0);
  EXPECT_NEAR(static_cast<double>(spaced_40hz.consecutive_matches),
              static_cast<double>(spaced.consecutive_matches),
              0.05 * static_cast<double>(spaced.consecutive_matches));
  std::printf("[ pairing ] chain matches: every scan %zu, spaced 0.25 s %zu (10 Hz), %zu (40 Hz)\n",
              every_scan.consecutive_matches, spaced.consecutive_matches,
              spaced_40hz.consecutive_matches);
  options.consecutive_min_spacing_s = -0.1;
  EXPECT_THROW(PairCollector(wheels(), options), std::invalid_argument);
}

TEST(PairCollector, AChainSpacingBeyondHalfTheIntervalIsTakenAsHalfOfIt)
{
  // 1 s at T = 0.5 s would chain only the keyframes (one coarse copy of each keyframe match,
  // which cannot catch its failures): T / 2 = 0.25 s is used, the same chain as 0.25 s.
  CollectorOptions options;
  options.consecutive_max_rays = 180;
  options.consecutive_min_spacing_s = 0.25;
  CollectorStatistics quarter, beyond;
  const std::vector<MotionPair> pairs = roomPairs(options, &quarter);
  options.consecutive_min_spacing_s = 1.0;
  ASSERT_EQ(roomPairs(options, &beyond).size(), pairs.size());
  EXPECT_EQ(beyond.consecutive_matches, quarter.consecutive_matches);
  EXPECT_GE(beyond.consecutive_matches, 2 * pairs.size());
}

TEST(PairCollector, AChainSpacingOfWholeLaserPeriodsKeepsItsScans)
{
  // 0.15 s is 6 periods of a 40 Hz laser: stamps a rounding error short of it still join, so
  // a 0.5 s interval chains 0, 0.15, 0.3, 0.45 and 0.5 s (4 matches), never 0.175 s steps.
  CollectorOptions options;
  options.consecutive_max_rays = 180;
  options.consecutive_min_spacing_s = 0.15;
  CollectorStatistics statistics;
  const std::vector<MotionPair> pairs = roomPairsAt(40.0, options, &statistics);
  ASSERT_GT(pairs.size(), 20u);
  const double per_interval = static_cast<double>(statistics.consecutive_matches) /
                              static_cast<double>(statistics.keyframes - 1);
  EXPECT_NEAR(per_interval, 4.0, 0.05);
}

TEST(PairCollector, ASpacedChainStillRejectsKeyframeMatchesThatFailSilently)
{
  // Every 4th keyframe match (the ones asked for a covariance) comes out converged but 10 cm
  // off: each is rejected by the check, with the chain spaced 0.25 s as without spacing.
  for (const double spacing_s : {0.0, 0.25}) {
    CollectorOptions options;
    options.consecutive_max_rays = 180;
    options.consecutive_min_spacing_s = spacing_s;
    options.background_matching = false;  // the keyframe matches counted in order
    std::size_t keyframe_matches = 0, corrupted = 0;
    options.matcher = [&](const PreparedScan& reference, const PreparedScan& current,
                          const Pose2& guess, const PlicpOptions& plicp) {
      PlicpResult result = matchScans(reference, current, guess, plicp);
      if (plicp.compute_covariance && ++keyframe_matches % 4 == 0 && result.valid()) {
        ++corrupted;
        result.T_ref_new = result.T_ref_new * Pose2(0.10, 0.0, 0.0);
      }
      return result;
    };
    CollectorStatistics statistics, clean_statistics;
    const std::vector<MotionPair> pairs = roomPairs(options, &statistics);
    options.matcher = nullptr;
    const std::vector<MotionPair> clean = roomPairs(options, &clean_statistics);
    ASSERT_GE(corrupted, 8u);
    EXPECT_EQ(pairs.size() + corrupted, clean.size()) << "spacing " << spacing_s << " s";
    EXPECT_EQ(statistics.consecutive_failures, 0u);
    EXPECT_EQ(statistics.rejected["keyframe match disagrees with consecutive matches"], corrupted)
        << "spacing " << spacing_s << " s";
    // A chain of its own scans, not the keyframe match's two again.
    EXPECT_GE(statistics.consecutive_matches, 2 * (statistics.keyframes - 1));
  }
}

TEST(PairCollector, PairMotionFromTheChainOfConsecutiveMatches)
{
  CollectorOptions options;
  CollectorStatistics direct_statistics, chain_statistics;
  const std::vector<MotionPair> direct = roomPairs(options, &direct_statistics);
  options.pair_motion_from_chain = true;
  const std::vector<MotionPair> chained = roomPairs(options, &chain_statistics);
  ASSERT_GT(direct.size(), 20u);
  // The same pairs (the consistency check kept the same ones), each with the chain's motion:
  // within the check's 3 cm / 0.02 rad of the direct match, and not the same numbers.
  ASSERT_EQ(chained.size(), direct.size());
  int differ = 0;
  for (std::size_t k = 0; k < direct.size(); ++k) {
    EXPECT_EQ(chained[k].start_stamp_s, direct[k].start_stamp_s);
    const Pose2 difference = between(direct[k].sensor_motion, chained[k].sensor_motion);
    EXPECT_LT(std::hypot(difference.x(), difference.y()), 0.03);
    EXPECT_LT(std::abs(difference.theta()), 0.02);
    differ += std::hypot(difference.x(), difference.y()) > 1e-6;
    EXPECT_EQ(chained[k].covariance, direct[k].covariance);  // the keyframe match's
  }
  EXPECT_GT(differ, static_cast<int>(direct.size()) / 2);
}

}  // namespace
}  // namespace odometry_calibration
