// The pair collector's matching: the same results whatever the background thread's timing (and
// with the keyframe matches deferred to the match queue, as calibrate_bag runs them), an
// injected matcher, scans prepared with the matcher's line-fit options.
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include <gtest/gtest.h>

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

/// Feeds one simulated run to two collectors: one matching in the background (its predictor
/// sleeps at random to shuffle the threads' timing), one matching in the calling thread; every
/// 13th scan is blanked so that matches fail. Compares what every call returned.
struct TwinFeeder : sim::SimulationSink
{
  PairCollector* background;
  PairCollector* inline_matching;
  std::size_t calls = 0, scans = 0, pairs = 0;
  void compare(const std::vector<CollectorEvent>& a, const std::vector<CollectorEvent>& b)
  {
    ++calls;
    ASSERT_EQ(a.size(), b.size()) << "call " << calls;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].type, b[i].type) << "call " << calls;
      EXPECT_EQ(a[i].reason, b[i].reason) << "call " << calls;
      EXPECT_EQ(a[i].pair.start_stamp_s, b[i].pair.start_stamp_s);
      EXPECT_EQ(a[i].pair.sensor_motion.vector(), b[i].pair.sensor_motion.vector());
      EXPECT_EQ(a[i].pair.covariance, b[i].pair.covariance);
      EXPECT_EQ(a[i].pair.encoder_samples.size(), b[i].pair.encoder_samples.size());
      pairs += a[i].type == CollectorEvent::Type::kPair;
    }
    if (calls % 37 == 0)  // mid-run statistics count the matches submitted so far
      compareStatistics();
  }
  void compareStatistics()
  {
    const CollectorStatistics& a = background->statistics();
    const CollectorStatistics& b = inline_matching->statistics();
    EXPECT_EQ(a.consecutive_matches, b.consecutive_matches) << "call " << calls;
    EXPECT_EQ(a.consecutive_failures, b.consecutive_failures) << "call " << calls;
    EXPECT_EQ(a.unverified_pairs, b.unverified_pairs);
    EXPECT_EQ(a.keyframes, b.keyframes);
    EXPECT_EQ(a.pairs, b.pairs);
    EXPECT_EQ(a.rejected, b.rejected);
  }
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::Vector2d raw(s.positions[0], s.positions[1]);
    compare(background->addEncoders(s.stamp_s, raw), inline_matching->addEncoders(s.stamp_s, raw));
  }
  void onScan(const sim::ScanSample& s) override
  {
    Scan scan = toScan(s);
    if (++scans % 13 == 0)
      scan.ranges_m.assign(scan.ranges_m.size(), 0.0);  // nothing usable: matches fail
    compare(background->addScan(s.stamp_s, scan), inline_matching->addScan(s.stamp_s, scan));
  }
  void onTruth(const sim::TruthSample&) override {}
  void onTracker(const sim::TrackerSample&) override {}
};

TEST(PairCollector, ResultsDoNotDependOnThreadTiming)
{
  const sim::Scenario s = scenario(40.0);
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  const DiffDriveEncoderLayout layout;
  auto nominal = [layout](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {0.077, 0.077, 0.33};
    return sensorMotionFromBodyMotion(Pose2(0.15, 0, 0),
                                      integrateDiffDriveMotion(intrinsic, layout, samples));
  };
  std::mt19937 random(5);
  MotionPredictor jittery = [&](const std::vector<EncoderSample>& samples) {
    std::this_thread::sleep_for(std::chrono::microseconds(random() % 700));
    return nominal(samples);
  };
  CollectorOptions options;
  PairCollector background(wheels(), options, jittery);
  options.background_matching = false;
  PairCollector inline_matching(wheels(), options, nominal);
  TwinFeeder feeder;
  feeder.background = &background;
  feeder.inline_matching = &inline_matching;
  sim::simulate(s, world, *robot, feeder);
  feeder.compare(background.flush(), inline_matching.flush());
  feeder.compareStatistics();
  // The blanked scans exercised the failure paths.
  const CollectorStatistics& stats = background.statistics();
  EXPECT_GT(feeder.pairs, 40u);
  EXPECT_GE(stats.consecutive_failures, 20u);
  EXPECT_GT(stats.unverified_pairs, 0u);
  EXPECT_FALSE(stats.rejected.empty());
  // A one-threaded run skips the matches after a failure until the next keyframe.
  EXPECT_LT(stats.consecutive_matches, stats.scans - 1);
}

/// Feeds one simulated run to a collector that defers its keyframe matches (matching in the
/// background, its predictor sleeping at random) and to one that matches in the calling thread;
/// every 11th scan is blanked so that matches fail. Gathers both event streams.
struct DeferredTwinFeeder : sim::SimulationSink
{
  PairCollector* deferred;
  PairCollector* inline_matching;
  std::vector<CollectorEvent> deferred_events, inline_events;
  std::size_t calls = 0, scans = 0;
  std::size_t late_calls = 0;  ///< calls where the deferred collector returned fewer events
  void take(std::vector<CollectorEvent> a, std::vector<CollectorEvent> b)
  {
    late_calls += a.size() < b.size() ? 1 : 0;
    deferred_events.insert(deferred_events.end(), a.begin(), a.end());
    inline_events.insert(inline_events.end(), b.begin(), b.end());
    // Mid-run statistics count the same, deferred events or not.
    if (++calls % 41 == 0) {
      EXPECT_EQ(deferred->statistics().pairs, inline_matching->statistics().pairs);
    }
  }
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::Vector2d raw(s.positions[0], s.positions[1]);
    take(deferred->addEncoders(s.stamp_s, raw), inline_matching->addEncoders(s.stamp_s, raw));
  }
  void onScan(const sim::ScanSample& s) override
  {
    Scan scan = toScan(s);
    if (++scans % 11 == 0)
      scan.ranges_m.assign(scan.ranges_m.size(), 0.0);  // nothing usable: matches fail
    take(deferred->addScan(s.stamp_s, scan), inline_matching->addScan(s.stamp_s, scan));
  }
  void onTruth(const sim::TruthSample&) override {}
  void onTracker(const sim::TrackerSample&) override {}
};

TEST(PairCollector, DeferredKeyframeMatchesGiveTheSameEventsInTheSameOrder)
{
  const sim::Scenario s = scenario(40.0);
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  const DiffDriveEncoderLayout layout;
  auto nominal = [layout](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {0.077, 0.077, 0.33};
    return sensorMotionFromBodyMotion(Pose2(0.15, 0, 0),
                                      integrateDiffDriveMotion(intrinsic, layout, samples));
  };
  std::mt19937 random(7);
  MotionPredictor jittery = [&](const std::vector<EncoderSample>& samples) {
    std::this_thread::sleep_for(std::chrono::microseconds(random() % 300));
    return nominal(samples);
  };
  CollectorOptions options;
  options.defer_keyframe_matches = true;
  PairCollector deferred(wheels(), options, jittery);
  options.defer_keyframe_matches = false;
  options.background_matching = false;
  PairCollector inline_matching(wheels(), options, nominal);
  DeferredTwinFeeder feeder;
  feeder.deferred = &deferred;
  feeder.inline_matching = &inline_matching;
  sim::simulate(s, world, *robot, feeder);
  feeder.take(deferred.flush(), inline_matching.flush());
  const std::vector<CollectorEvent>& a = feeder.deferred_events;
  const std::vector<CollectorEvent>& b = feeder.inline_events;
  ASSERT_EQ(a.size(), b.size());
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].type, b[i].type) << "event " << i;
    EXPECT_EQ(a[i].reason, b[i].reason) << "event " << i;
    EXPECT_EQ(a[i].pair.start_stamp_s, b[i].pair.start_stamp_s);
    EXPECT_EQ(a[i].pair.end_stamp_s, b[i].pair.end_stamp_s);
    EXPECT_EQ(a[i].pair.sensor_motion.vector(), b[i].pair.sensor_motion.vector());
    EXPECT_EQ(a[i].pair.covariance, b[i].pair.covariance);
    EXPECT_EQ(a[i].pair.encoder_samples.size(), b[i].pair.encoder_samples.size());
    pairs += a[i].type == CollectorEvent::Type::kPair;
  }
  EXPECT_GT(pairs, 40u);
  const CollectorStatistics& x = deferred.statistics();
  const CollectorStatistics& y = inline_matching.statistics();
  EXPECT_EQ(x.pairs, pairs);
  EXPECT_EQ(x.consecutive_matches, y.consecutive_matches);
  EXPECT_EQ(x.consecutive_failures, y.consecutive_failures);
  EXPECT_GE(x.consecutive_failures, 20u);
  EXPECT_EQ(x.unverified_pairs, y.unverified_pairs);
  EXPECT_EQ(x.keyframes, y.keyframes);
  EXPECT_EQ(x.rejected, y.rejected);
  EXPECT_FALSE(x.rejected.empty());
  EXPECT_EQ(x.scale_check_pairs, y.scale_check_pairs);
  EXPECT_EQ(x.chained_m, y.chained_m);
  // The deferral happened: some events came on a later call than the inline collector's.
  EXPECT_GT(feeder.late_calls, 0u);
}

TEST(PairCollector, AnInjectedMatcherMakesEveryMatch)
{
  CollectorOptions options;
  CollectorStatistics plain_statistics, statistics;
  const std::vector<MotionPair> plain = roomPairs(options, &plain_statistics);
  std::atomic<int> keyframe_matches{0}, consecutive_matches{0};
  options.matcher = [&](const PreparedScan& reference, const PreparedScan& current,
                        const Pose2& guess, const PlicpOptions& plicp) {
    // The pairing asks for the covariance of keyframe matches only.
    ++(plicp.compute_covariance ? keyframe_matches : consecutive_matches);
    return matchScans(reference, current, guess, plicp);
  };
  const std::vector<MotionPair> wrapped = roomPairs(options, &statistics);
  ASSERT_GT(plain.size(), 20u);
  ASSERT_EQ(wrapped.size(), plain.size());
  for (std::size_t k = 0; k < plain.size(); ++k)
    EXPECT_EQ(wrapped[k].sensor_motion.x(), plain[k].sensor_motion.x());
  EXPECT_EQ(static_cast<std::size_t>(consecutive_matches), statistics.consecutive_matches);
  EXPECT_GE(static_cast<std::size_t>(keyframe_matches), plain.size());

  // A matcher that never converges: no pair, every keyframe interval rejected for it.
  options.matcher = [](const PreparedScan&, const PreparedScan&, const Pose2& guess,
                       const PlicpOptions&) {
    PlicpResult result;
    result.status = PlicpStatus::kNoConvergence;
    result.T_ref_new = guess;
    return result;
  };
  EXPECT_TRUE(roomPairs(options, &statistics).empty());
  EXPECT_GT(statistics.rejected["scan match " + std::string(toString(PlicpStatus::kNoConvergence))],
            20u);
}

TEST(PairCollector, ScansArePreparedWithTheMatchersLineFitOptions)
{
  // The line fits of scan_matching in a configuration (plicp.line_fit) reach every scan the
  // collector prepares: once they were read from a second copy that nothing set.
  CollectorOptions options;
  std::atomic<long> matches{0}, points{0};
  options.matcher = [&](const PreparedScan& reference, const PreparedScan& current,
                        const Pose2& guess, const PlicpOptions& plicp) {
    ++matches;
    points += static_cast<long>(reference.points.size() + current.points.size());
    return matchScans(reference, current, guess, plicp);
  };
  CollectorStatistics statistics;
  ASSERT_GT(roomPairs(options, &statistics).size(), 20u);
  ASSERT_GT(matches, 0);
  const double mean_points = static_cast<double>(points) / static_cast<double>(matches);
  // A veiling angle of 80 degrees drops every point whose ray meets its neighbour's segment at
  // less than 80 degrees: most of each scan of the 10 m x 8 m room.
  matches = 0;
  points = 0;
  options.plicp.line_fit.veiling_min_angle_rad = 80.0 * M_PI / 180.0;
  roomPairs(options, &statistics);
  ASSERT_GT(matches, 0);
  const double veiled_mean_points = static_cast<double>(points) / static_cast<double>(matches);
  std::printf("[ pairing ] points per match: %.0f, with an 80 degree veiling filter %.0f\n",
              mean_points, veiled_mean_points);
  EXPECT_LT(veiled_mean_points, 0.7 * mean_points);
}

}  // namespace
}  // namespace odometry_calibration
