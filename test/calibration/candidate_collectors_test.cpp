// Pairs at several keyframe intervals from one stream (the node's fit-interval candidates).
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace {

std::vector<EncoderChannelOptions> wheels()
{
  return {{"left_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0},
          {"right_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0}};
}

const Eigen::Matrix3d kTrackerCovariance = Eigen::Vector3d(1e-5, 1e-5, 1e-6).asDiagonal();

/// Feeds a simulated tracker run to the node's own collector and to the candidates.
struct Feeder : sim::SimulationSink
{
  PairCollector* main = nullptr;
  CandidateCollectors* candidates = nullptr;
  std::vector<MotionPair> main_pairs;
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::VectorXd raw = Eigen::Map<const Eigen::VectorXd>(s.positions.data(), 2);
    take(main->addEncoders(s.stamp_s, raw));
    candidates->addEncoders(s.stamp_s, raw);
  }
  void onScan(const sim::ScanSample&) override {}
  void onTruth(const sim::TruthSample&) override {}
  void onTracker(const sim::TrackerSample& s) override
  {
    take(main->addSensorPose(s.stamp_s, s.T_world_sensor, kTrackerCovariance));
    candidates->addSensorPose(s.stamp_s, s.T_world_sensor, kTrackerCovariance);
  }
  void take(const std::vector<CollectorEvent>& events)
  {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        main_pairs.push_back(event.pair);
    }
  }
};

TEST(CandidateCollectors, PairsAtEachIntervalFromOneStream)
{
  sim::Scenario scenario;
  scenario.duration_s = 30.0;
  scenario.encoders.rate_hz = 50.0;
  scenario.tracker.enabled = true;
  const sim::World world =
      sim::parseWorldYaml("polygons: [[[-5, -4], [5, -4], [5, 4], [-5, 4]]]\n", "room");
  const auto robot = sim::makeRobot(scenario.robot);
  CollectorOptions options;  // keyframes every 0.5 s
  PairCollector main(wheels(), options);
  CandidateCollectors candidates(wheels(), options, nullptr, {0.3, 0.5, 1.0});
  Feeder feeder;
  feeder.main = &main;
  feeder.candidates = &candidates;
  sim::simulate(scenario, world, *robot, feeder);
  feeder.take(main.flush());
  candidates.flush();

  const std::vector<IntervalPairs> pairs = candidates.pairs();
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].interval_s, 0.3);
  EXPECT_EQ(pairs[2].interval_s, 1.0);
  // 30 s of tracker poses: about 30 / T pairs at each interval.
  EXPECT_NEAR(static_cast<double>(pairs[0].pairs.size()), 30.0 / 0.3, 8.0);
  EXPECT_NEAR(static_cast<double>(pairs[2].pairs.size()), 30.0 / 1.0, 3.0);
  for (const MotionPair& pair : pairs[2].pairs)
    EXPECT_NEAR(pair.end_stamp_s - pair.start_stamp_s, 1.0, 0.05);
  // The 0.5 s candidate is the node's own collector again, pair for pair.
  ASSERT_EQ(pairs[1].pairs.size(), feeder.main_pairs.size());
  for (std::size_t k = 0; k < feeder.main_pairs.size(); ++k) {
    EXPECT_EQ(pairs[1].pairs[k].start_stamp_s, feeder.main_pairs[k].start_stamp_s);
    EXPECT_EQ(pairs[1].pairs[k].sensor_motion.x(), feeder.main_pairs[k].sensor_motion.x());
    EXPECT_EQ(pairs[1].pairs[k].encoder_samples.size(),
              feeder.main_pairs[k].encoder_samples.size());
  }

  candidates.clear();
  for (const IntervalPairs& candidate : candidates.pairs())
    EXPECT_TRUE(candidate.pairs.empty());
}

TEST(CandidateCollectors, RefusesBadIntervals)
{
  EXPECT_THROW(CandidateCollectors(wheels(), CollectorOptions(), nullptr, {0.5, 0.0}),
               std::invalid_argument);
  EXPECT_THROW(CandidateCollectors(wheels(), CollectorOptions(), nullptr, {NAN}),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
