#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_kinematics.h"
#include "odometry_calibration/pairing/decimated_scan.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

std::vector<EncoderChannelOptions> wheels()
{
  return {{"left_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0},
          {"right_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0}};
}

using test::toScan;

/// Feeds a simulated run to a collector in time order, as the node and the bag tool do.
struct Feeder : sim::SimulationSink
{
  PairCollector* collector;
  bool use_tracker = false;
  std::vector<MotionPair> pairs;
  std::vector<double> truth_stamps;
  std::vector<Pose2> truth;
  void onJointState(const sim::JointStateSample& s) override
  {
    take(collector->addEncoders(s.stamp_s,
                                Eigen::Map<const Eigen::VectorXd>(s.positions.data(), 2)));
  }
  void onScan(const sim::ScanSample& s) override
  {
    if (!use_tracker)
      take(collector->addScan(s.stamp_s, toScan(s)));
  }
  void onTruth(const sim::TruthSample& s) override
  {
    truth_stamps.push_back(s.stamp_s);
    truth.push_back(s.T_world_base);
  }
  void onTracker(const sim::TrackerSample& s) override
  {
    if (use_tracker) {
      take(collector->addSensorPose(s.stamp_s, s.T_world_sensor,
                                    Eigen::Vector3d(1e-5, 1e-5, 1e-6).asDiagonal()));
    }
  }
  void take(const std::vector<CollectorEvent>& events)
  {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs.push_back(event.pair);
    }
  }
  Pose2 truthAt(double t) const
  {
    for (std::size_t k = 0; k < truth_stamps.size(); ++k) {
      if (std::abs(truth_stamps[k] - t) < 1e-9)
        return truth[k];
    }
    ADD_FAILURE() << "no truth at " << t;
    return Pose2();
  }
};

sim::Scenario scenario(double duration_s)
{
  sim::Scenario s;
  s.duration_s = duration_s;
  s.laser.rays = 682;
  s.laser.fov_rad = 4.18879;
  s.laser.T_base_laser = Pose2(0.15, 0.0, 0.0);
  s.encoders.rate_hz = 50.0;
  s.motion.max_speed_mps = 0.4;
  s.motion.max_turn_rate_radps = 0.8;
  return s;
}

const char* kRoom =
    "polygons: [[[-5, -4], [5, -4], [5, 4], [-5, 4]]]\n"
    "boxes: [{center: [2.5, 2.0], size: [1.0, 0.6]}, {center: [-3, -2.5], size: [0.8, 0.8]}]\n"
    "circles: [{center: [-2.0, 2.2], radius: 0.3}]\n";

TEST(PairCollector, ScanPairsMatchTheTrueSensorMotion)
{
  const sim::Scenario s = scenario(30.0);
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  CollectorOptions options;
  options.keyframe_interval_s = 0.5;
  // The nominal model as the matcher's initial guess.
  const DiffDriveEncoderLayout layout;
  MotionPredictor predictor = [layout](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {0.077, 0.077, 0.33};
    return sensorMotionFromBodyMotion(Pose2(0.15, 0, 0),
                                      integrateDiffDriveMotion(intrinsic, layout, samples));
  };
  PairCollector collector(wheels(), options, predictor);
  Feeder feeder;
  feeder.collector = &collector;
  sim::simulate(s, world, *robot, feeder);

  ASSERT_GT(feeder.pairs.size(), 40u);
  int off = 0;
  for (const MotionPair& pair : feeder.pairs) {
    EXPECT_NEAR(pair.end_stamp_s - pair.start_stamp_s, 0.5, 1e-6);
    const Pose2 truth = between(feeder.truthAt(pair.start_stamp_s) * s.laser.T_base_laser,
                                feeder.truthAt(pair.end_stamp_s) * s.laser.T_base_laser);
    const Pose2 error = between(truth, pair.sensor_motion);
    off += std::hypot(error.x(), error.y()) > 0.01 || std::abs(error.theta()) > 0.005;
    // The encoder window spans the interval exactly.
    EXPECT_NEAR(pair.encoder_samples.front().stamp_s, pair.start_stamp_s, 1e-9);
    EXPECT_NEAR(pair.encoder_samples.back().stamp_s, pair.end_stamp_s, 1e-9);
    EXPECT_GT(pair.covariance(0, 0), 0.0);
  }
  EXPECT_LE(off, 1) << "pairs more than 1 cm / 0.3 deg off the truth";
  const CollectorStatistics& stats = collector.statistics();
  EXPECT_EQ(stats.pairs, feeder.pairs.size());
  EXPECT_EQ(stats.scans, 301u);
}

TEST(PairCollector, SensorPoseSourceAndTimeOffset)
{
  sim::Scenario s = scenario(20.0);
  s.tracker.enabled = true;
  s.tracker.translation_noise_m = 0.0;
  s.tracker.rotation_noise_rad = 0.0;
  s.encoders.time_offset_s = -0.15;  // encoder stamps early by 0.15 s
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  CollectorOptions options;
  options.time_offset_s = -0.15;  // ... which the collector undoes
  PairCollector collector(wheels(), options);
  Feeder feeder;
  feeder.collector = &collector;
  feeder.use_tracker = true;
  sim::simulate(s, world, *robot, feeder);
  ASSERT_GT(feeder.pairs.size(), 30u);
  // With the offset undone, the encoder increments of a pair are those of its true interval:
  // the ideal kinematics reproduce the measured (noise-free) motion to tick quantisation.
  const double intrinsic[3] = {0.077, 0.077, 0.33};
  double worst = 0.0;
  for (const MotionPair& pair : feeder.pairs) {
    const Pose2 predicted = sensorMotionFromBodyMotion(
        s.laser.T_base_laser,
        integrateDiffDriveMotion(intrinsic, DiffDriveEncoderLayout(), pair.encoder_samples));
    const Pose2 error = between(pair.sensor_motion, predicted);
    worst = std::max(worst, std::hypot(error.x(), error.y()));
  }
  EXPECT_LT(worst, 0.003);
}

TEST(PairCollector, RestartsWhenTimeGoesBackwardsAndRejectsEncoderGaps)
{
  PairCollector collector(wheels(), CollectorOptions());
  const Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-4;
  for (int k = 0; k <= 50; ++k)
    collector.addEncoders(0.02 * k, Eigen::Vector2d(10 * k, 10 * k));
  auto only = [](const std::vector<CollectorEvent>& events) {
    EXPECT_EQ(events.size(), 1u);
    return events.empty() ? CollectorEvent() : events.front();
  };
  EXPECT_EQ(only(collector.addSensorPose(0.0, Pose2(), covariance)).type,
            CollectorEvent::Type::kKeyframe);
  EXPECT_EQ(only(collector.addSensorPose(0.5, Pose2(0.1, 0, 0), covariance)).type,
            CollectorEvent::Type::kPair);
  // A pose ahead of the encoders waits for them (equal stamps come in either order).
  EXPECT_TRUE(collector.addSensorPose(1.4, Pose2(0.2, 0, 0), covariance).empty());
  // The encoders were silent for 0.4 s: no pair over that interval.
  const CollectorEvent gap = only(collector.addEncoders(1.4, Eigen::Vector2d(700, 700)));
  EXPECT_EQ(gap.type, CollectorEvent::Type::kRejected);
  EXPECT_NE(gap.reason.find("encoder"), std::string::npos) << gap.reason;
  // A looping bag: time jumps back.
  const CollectorEvent back = only(collector.addSensorPose(0.1, Pose2(), covariance));
  EXPECT_EQ(back.type, CollectorEvent::Type::kRestarted);
  EXPECT_EQ(collector.statistics().restarts, 1u);
  EXPECT_EQ(collector.statistics().pairs, 1u);
}

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

TEST(PairCollector, MinimumMotionExtendsIntervalsAndDropsStandingStill)
{
  CollectorOptions options;
  options.min_translation_m = 0.05;
  options.min_rotation_rad = 0.05;
  // 1000 ticks per metre, straight ahead.
  MotionPredictor predictor = [](const std::vector<EncoderSample>& samples) {
    return Pose2((samples.back().values(0) - samples.front().values(0)) / 1000.0, 0.0, 0.0);
  };
  PairCollector collector(wheels(), options, predictor);
  // Driving for 1 s, standing for 3 s, driving again until 5 s (10 ticks per 20 ms).
  double ticks = 0.0;
  std::vector<std::pair<double, double>> pairs;
  std::vector<std::string> rejected;
  auto take = [&](const std::vector<CollectorEvent>& events) {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs.emplace_back(event.pair.start_stamp_s, event.pair.end_stamp_s);
      if (event.type == CollectorEvent::Type::kRejected)
        rejected.push_back(event.reason);
    }
  };
  const Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-4;
  for (int k = 0; k <= 250; ++k) {
    const double t = 0.02 * k;
    if (k > 0 && (t <= 1.0 + 1e-9 || t > 4.0 + 1e-9))
      ticks += 10.0;
    take(collector.addEncoders(t, Eigen::Vector2d(ticks, ticks)));
    if (k % 5 == 0)
      take(collector.addSensorPose(t, Pose2(ticks / 1000.0, 0, 0), covariance));
  }
  take(collector.flush());
  const std::vector<std::pair<double, double>> expected = {
      {0.0, 0.5}, {0.5, 1.0}, {3.0, 4.1}, {4.1, 4.6}};  // 4.1: 5 cm since driving on
  ASSERT_EQ(pairs.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(pairs[i].first, expected[i].first, 1e-9) << i;
    EXPECT_NEAR(pairs[i].second, expected[i].second, 1e-9) << i;
  }
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_NE(rejected[0].find("too little motion"), std::string::npos) << rejected[0];
}

/// The nominal model as the matchers' initial guess (laser at x = 0.15).
MotionPredictor nominalPredictor()
{
  const DiffDriveEncoderLayout layout;
  return [layout](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {0.077, 0.077, 0.33};
    return sensorMotionFromBodyMotion(Pose2(0.15, 0, 0),
                                      integrateDiffDriveMotion(intrinsic, layout, samples));
  };
}

/// The pairs of a 20 s run in the room with `options`.
std::vector<MotionPair> roomPairs(const CollectorOptions& options, CollectorStatistics* statistics)
{
  const sim::Scenario s = scenario(20.0);
  const sim::World world = sim::parseWorldYaml(kRoom, "room");
  const auto robot = sim::makeRobot(s.robot);
  PairCollector collector(wheels(), options, nominalPredictor());
  Feeder feeder;
  feeder.collector = &collector;
  sim::simulate(s, world, *robot, feeder);
  feeder.take(collector.flush());
  *statistics = collector.statistics();
  return feeder.pairs;
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

TEST(PairCollector, NearestEncoderReadingAtTheKeyframes)
{
  CollectorOptions options;
  options.time_offset_s = 0.007;  // keyframes 7 ms after a 50 Hz reading
  CollectorStatistics statistics;
  const std::vector<MotionPair> linear = roomPairs(options, &statistics);
  options.encoder_interpolation = EncoderInterpolation::kNearest;
  const std::vector<MotionPair> nearest = roomPairs(options, &statistics);
  ASSERT_GT(linear.size(), 20u);
  ASSERT_EQ(nearest.size(), linear.size());
  int moving = 0;
  for (std::size_t k = 0; k < linear.size(); ++k) {
    const auto& l = linear[k].encoder_samples;
    const auto& n = nearest[k].encoder_samples;
    ASSERT_EQ(n.size(), l.size());
    ASSERT_GE(n.size(), 3u);
    EXPECT_NEAR(n.front().stamp_s, linear[k].start_stamp_s + 0.007, 1e-9);
    // Linear: 35 % of the way to the next reading (l[1]); nearest: the reading before, so the
    // linear value lies between it and the next one, 0.35 of the step from it.
    const Eigen::VectorXd step = l[1].values - n.front().values;
    if (step.norm() > 1.0) {
      ++moving;
      EXPECT_NEAR((l.front().values - n.front().values).norm(), 0.35 * step.norm(),
                  1e-6 * step.norm() + 1e-9);
    }
    EXPECT_EQ(n[1].values, l[1].values);  // the readings inside are the same
  }
  EXPECT_GT(moving, 10);
}

/// Durations of the pairs of a 20 s straight drive with sensor poses at `rate_hz` and
/// encoders at 100 Hz, stamped as a bag's are (an epoch offset, so the stamps' differences carry
/// rounding errors).
std::vector<double> pairDurations(double interval_s, double rate_hz)
{
  CollectorOptions options;
  options.keyframe_interval_s = interval_s;
  MotionPredictor predictor = [](const std::vector<EncoderSample>& samples) {
    return Pose2((samples.back().values(0) - samples.front().values(0)) / 1000.0, 0.0, 0.0);
  };
  PairCollector collector(wheels(), options, predictor);
  std::vector<double> durations;
  auto take = [&](const std::vector<CollectorEvent>& events) {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        durations.push_back(event.pair.end_stamp_s - event.pair.start_stamp_s);
    }
  };
  const double t0_s = 1700000000.123;
  const Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-4;
  const int pose_every = static_cast<int>(std::lround(400.0 / rate_hz));  // of 400 Hz ticks
  for (int k = 0; k <= 8000; ++k) {
    const double elapsed_s = k / 400.0;
    if (k % 4 == 0) {
      take(collector.addEncoders(t0_s + elapsed_s, Eigen::Vector2d(k, k)));
    }
    if (k % pose_every == 0)
      take(collector.addSensorPose(t0_s + elapsed_s, Pose2(k / 1000.0, 0, 0), covariance));
  }
  take(collector.flush());
  return durations;
}

TEST(PairCollector, PairsLastTheAskedIntervalAt10HzAnd40Hz)
{
  // 0.3 s on a 10 Hz input gave 0.4 s pairs: the sum of three periods fell a rounding error short.
  const std::vector<double> at_10_hz = pairDurations(0.3, 10.0);
  ASSERT_GE(at_10_hz.size(), 60u);
  for (const double duration_s : at_10_hz)
    ASSERT_NEAR(duration_s, 0.3, 1e-5);
  const std::vector<double> at_40_hz = pairDurations(0.25, 40.0);
  ASSERT_GE(at_40_hz.size(), 75u);
  for (const double duration_s : at_40_hz)
    ASSERT_NEAR(duration_s, 0.25, 1e-5);
}

TEST(PairCollector, PairsLastTheIntervalWithinHalfAPeriodOverTheRange)
{
  for (const double rate_hz : {10.0, 40.0}) {
    for (int step = 0; step <= 15; ++step) {
      const double interval_s = 0.25 + 0.05 * step;
      const std::vector<double> durations = pairDurations(interval_s, rate_hz);
      ASSERT_GE(durations.size(), static_cast<std::size_t>(19.0 / (interval_s + 0.05)));
      for (const double duration_s : durations) {
        ASSERT_LE(std::abs(duration_s - interval_s), 0.5 / rate_hz + 1e-5)
            << interval_s << " s at " << rate_hz << " Hz";
      }
    }
  }
}

TEST(PairCollector, InvalidOptionsAreNamed)
{
  CollectorOptions options;
  options.keyframe_interval_s = 0.0;
  try {
    PairCollector collector(wheels(), options);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("keyframe_interval_s"), std::string::npos);
  }
  options = CollectorOptions();
  options.pair_motion_from_chain = true;
  options.check_consistency = false;
  try {
    PairCollector collector(wheels(), options);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("pair_motion_from_chain"), std::string::npos);
  }
}

}  // namespace
}  // namespace odometry_calibration
