// The pair collector's matching: the same results whatever the background thread's timing (and
// with the keyframe matches deferred to the match queue, as calibrate_bag runs them), an
// injected matcher, scans prepared with the matcher's line-fit options.
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <string>
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

/// Feeds one simulated run to two collectors, `first` and `second` (the one under test and one
/// matching in the calling thread), handing what each call of both returned to `take`; every
/// `blank_every`-th scan is blanked so that matches fail.
struct TwinFeeder : sim::SimulationSink
{
  using Take =
      std::function<void(const std::vector<CollectorEvent>&, const std::vector<CollectorEvent>&)>;
  PairCollector* first;
  PairCollector* second;
  std::size_t blank_every;
  Take take;
  std::size_t scans = 0;
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::Vector2d raw(s.positions[0], s.positions[1]);
    take(first->addEncoders(s.stamp_s, raw), second->addEncoders(s.stamp_s, raw));
  }
  void onScan(const sim::ScanSample& s) override
  {
    Scan scan = toScan(s);
    if (++scans % blank_every == 0)
      scan.ranges_m.assign(scan.ranges_m.size(), 0.0);  // nothing usable: matches fail
    take(first->addScan(s.stamp_s, scan), second->addScan(s.stamp_s, scan));
  }
  void onTruth(const sim::TruthSample&) override {}
  void onTracker(const sim::TrackerSample&) override {}
};

/// The 40 s room run fed to `first` and `second` (TwinFeeder), then both flushed into `take`.
void feedTwins(PairCollector& first, PairCollector& second, std::size_t blank_every,
               const TwinFeeder::Take& take)
{
  const sim::Scenario s = scenario(40.0);
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  TwinFeeder feeder;
  feeder.first = &first;
  feeder.second = &second;
  feeder.blank_every = blank_every;
  feeder.take = take;
  sim::simulate(s, world, *robot, feeder);
  take(first.flush(), second.flush());
}

/// The nominal guess (nominalPredictor) after a random sleep of up to `max_sleep_us`, so that
/// a background thread's timing is shuffled.
MotionPredictor jitteryNominal(std::mt19937* random, unsigned max_sleep_us)
{
  return [random, max_sleep_us,
          nominal = nominalPredictor()](const std::vector<EncoderSample>& samples) {
    std::this_thread::sleep_for(std::chrono::microseconds((*random)() % max_sleep_us));
    return nominal(samples);
  };
}

/// The two collectors' mid-run statistics agree (counting the matches submitted so far).
void expectSameStatistics(const PairCollector& a_collector, const PairCollector& b_collector,
                          std::size_t call)
{
  const CollectorStatistics& a = a_collector.statistics();
  const CollectorStatistics& b = b_collector.statistics();
  EXPECT_EQ(a.consecutive_matches, b.consecutive_matches) << "call " << call;
  EXPECT_EQ(a.consecutive_failures, b.consecutive_failures) << "call " << call;
  EXPECT_EQ(a.unverified_pairs, b.unverified_pairs);
  EXPECT_EQ(a.keyframes, b.keyframes);
  EXPECT_EQ(a.pairs, b.pairs);
  EXPECT_EQ(a.rejected, b.rejected);
}

/// Two events are the same: type, reason and pair.
void expectSameEvent(const CollectorEvent& a, const CollectorEvent& b, const std::string& where)
{
  EXPECT_EQ(a.type, b.type) << where;
  EXPECT_EQ(a.reason, b.reason) << where;
  EXPECT_EQ(a.pair.start_stamp_s, b.pair.start_stamp_s) << where;
  EXPECT_EQ(a.pair.end_stamp_s, b.pair.end_stamp_s) << where;
  EXPECT_EQ(a.pair.sensor_motion.vector(), b.pair.sensor_motion.vector()) << where;
  EXPECT_EQ(a.pair.covariance, b.pair.covariance) << where;
  EXPECT_EQ(a.pair.encoder_samples.size(), b.pair.encoder_samples.size()) << where;
}

TEST(PairCollector, ResultsDoNotDependOnThreadTiming)
{
  // One collector matching in the background (its predictor sleeping at random), one in the
  // calling thread; every 13th scan blanked. What every call returned is compared.
  std::mt19937 random(5);
  CollectorOptions options;
  PairCollector background(wheels(), options, jitteryNominal(&random, 700));
  options.background_matching = false;
  PairCollector inline_matching(wheels(), options, nominalPredictor());
  std::size_t calls = 0, pairs = 0;
  feedTwins(background, inline_matching, 13,
            [&](const std::vector<CollectorEvent>& a, const std::vector<CollectorEvent>& b) {
              ++calls;
              ASSERT_EQ(a.size(), b.size()) << "call " << calls;
              for (std::size_t i = 0; i < a.size(); ++i) {
                expectSameEvent(a[i], b[i], "call " + std::to_string(calls));
                pairs += a[i].type == CollectorEvent::Type::kPair;
              }
              if (calls % 37 == 0)
                expectSameStatistics(background, inline_matching, calls);
            });
  expectSameStatistics(background, inline_matching, calls);
  // The blanked scans exercised the failure paths.
  const CollectorStatistics& stats = background.statistics();
  EXPECT_GT(pairs, 40u);
  EXPECT_GE(stats.consecutive_failures, 20u);
  EXPECT_GT(stats.unverified_pairs, 0u);
  EXPECT_FALSE(stats.rejected.empty());
  // A one-threaded run skips the matches after a failure until the next keyframe.
  EXPECT_LT(stats.consecutive_matches, stats.scans - 1);
}

TEST(PairCollector, DeferredKeyframeMatchesGiveTheSameEventsInTheSameOrder)
{
  // A collector deferring its keyframe matches (matching in the background, its predictor
  // sleeping at random) against one matching in the calling thread; every 11th scan blanked.
  // Both event streams are gathered and compared whole.
  std::mt19937 random(7);
  CollectorOptions options;
  options.defer_keyframe_matches = true;
  PairCollector deferred(wheels(), options, jitteryNominal(&random, 300));
  options.defer_keyframe_matches = false;
  options.background_matching = false;
  PairCollector inline_matching(wheels(), options, nominalPredictor());
  std::vector<CollectorEvent> a, b;
  std::size_t calls = 0;
  std::size_t late_calls = 0;  // calls where the deferred collector returned fewer events
  feedTwins(
      deferred, inline_matching, 11,
      [&](const std::vector<CollectorEvent>& first, const std::vector<CollectorEvent>& second) {
        late_calls += first.size() < second.size() ? 1 : 0;
        a.insert(a.end(), first.begin(), first.end());
        b.insert(b.end(), second.begin(), second.end());
        // Mid-run statistics count the same, deferred events or not.
        if (++calls % 41 == 0) {
          EXPECT_EQ(deferred.statistics().pairs, inline_matching.statistics().pairs);
        }
      });
  ASSERT_EQ(a.size(), b.size());
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    expectSameEvent(a[i], b[i], "event " + std::to_string(i));
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
  EXPECT_GT(late_calls, 0u);
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
