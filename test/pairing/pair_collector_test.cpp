// The pair collector (pairing/pair_collector.h): pairs of scans and of sensor poses against the
// true motion, time going backwards and encoder gaps, the minimum motion, the encoder reading
// nearest a keyframe, the pairs' durations, invalid options.
#include <cmath>

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
  // The encoders were silent for 0.4 s: no pair over that interval, said once the reading after
  // the pose's is there (the cubic between the readings takes its slope from that one).
  EXPECT_TRUE(collector.addEncoders(1.4, Eigen::Vector2d(700, 700)).empty());
  const CollectorEvent gap = only(collector.addEncoders(1.42, Eigen::Vector2d(710, 710)));
  EXPECT_EQ(gap.type, CollectorEvent::Type::kRejected);
  EXPECT_NE(gap.reason.find("encoder"), std::string::npos) << gap.reason;
  // A looping bag: time jumps back.
  const CollectorEvent back = only(collector.addSensorPose(0.1, Pose2(), covariance));
  EXPECT_EQ(back.type, CollectorEvent::Type::kRestarted);
  EXPECT_EQ(collector.statistics().restarts, 1u);
  EXPECT_EQ(collector.statistics().pairs, 1u);
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

TEST(PairCollector, NearestEncoderReadingAtTheKeyframes)
{
  CollectorOptions options;
  options.time_offset_s = 0.007;  // keyframes 7 ms after a 50 Hz reading
  options.encoder_interpolation = EncoderInterpolation::kLinear;
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

// Encoders read every 0.26 s (a slow driver loop): the derived gap limit pairs them; a configured
// 0.25 s rejects every interval and is named with the spacing and the value to set; a keyframe
// interval shorter than the spacing is named too.
TEST(PairCollector, TheEncoderGapFollowsTheReadingsAndAContradictingValueIsNamed)
{
  const Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-4;
  auto drive = [&](PairCollector& collector) {
    std::size_t pairs = 0, rejected = 0;
    auto count = [&](const std::vector<CollectorEvent>& events) {
      for (const CollectorEvent& event : events) {
        pairs += event.type == CollectorEvent::Type::kPair;
        rejected += event.type == CollectorEvent::Type::kRejected;
      }
    };
    for (int k = 0; k <= 40; ++k) {
      count(collector.addEncoders(0.26 * k, Eigen::Vector2d(100 * k, 100 * k)));
      count(collector.addSensorPose(0.26 * k + 0.01, Pose2(0.01 * k, 0, 0), covariance));
    }
    return std::make_pair(pairs, rejected);
  };
  PairCollector derived(wheels(), CollectorOptions());
  const auto [pairs, rejected] = drive(derived);
  EXPECT_GE(pairs, 15u);
  EXPECT_EQ(rejected, 0u);
  EXPECT_NEAR(derived.encoderGapLimit_s(), 0.65, 1e-9);  // 2.5 x 0.26 s
  EXPECT_NEAR(derived.statistics().encoder_spacing_median_s, 0.26, 1e-9);
  EXPECT_EQ(derived.configurationConflict(), "");

  CollectorOptions configured;
  configured.max_encoder_gap_s = 0.25;
  PairCollector refused(wheels(), configured);
  const auto [none, all] = drive(refused);
  EXPECT_EQ(none, 0u);
  EXPECT_GE(all, 15u);
  EXPECT_EQ(refused.statistics().rejected.count(kNoEncoderReadingReason) +
                refused.statistics().rejected.count(kEncoderGapReason),
            refused.statistics().rejected.size());
  const std::string conflict = refused.configurationConflict();
  for (const char* part : {"keyframes.max_encoder_gap_s = 0.25 s", "every 0.26 s",
                           "median of 40 spacings", "at least 0.65"})
    EXPECT_NE(conflict.find(part), std::string::npos) << part << " in: " << conflict;

  CollectorOptions short_interval;
  short_interval.keyframe_interval_s = 0.2;
  PairCollector too_short(wheels(), short_interval);
  drive(too_short);
  EXPECT_NE(too_short.configurationConflict().find(
                "keyframes.interval_s = 0.2 s is shorter than the encoder readings' spacing, "
                "0.26 s (median of 40)"),
            std::string::npos)
      << too_short.configurationConflict();
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
