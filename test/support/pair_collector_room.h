// What the pair collector's tests share (test/pairing/pair_collector*_test.cpp): two wheels,
// a simulated room and robot, a feeder giving a run to a collector in time order, the nominal
// diff drive as the matchers' initial guess.
#pragma once

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_kinematics.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

#include "support/sim_recording.h"

namespace odometry_calibration {
namespace test {

/// Two incremental wheel joints, left_wheel and right_wheel, wrapping at 2^32 ticks.
inline std::vector<EncoderChannelOptions> wheels()
{
  return {{"left_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0},
          {"right_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0}};
}

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

inline sim::Scenario scenario(double duration_s)
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

/// A 10 m x 8 m room with two boxes and a pillar (sim world YAML).
inline const char* const kRoom =
    "polygons: [[[-5, -4], [5, -4], [5, 4], [-5, 4]]]\n"
    "boxes: [{center: [2.5, 2.0], size: [1.0, 0.6]}, {center: [-3, -2.5], size: [0.8, 0.8]}]\n"
    "circles: [{center: [-2.0, 2.2], radius: 0.3}]\n";

/// The nominal model as the matchers' initial guess (laser at x = 0.15).
inline MotionPredictor nominalPredictor()
{
  const DiffDriveEncoderLayout layout;
  return [layout](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {0.077, 0.077, 0.33};
    return sensorMotionFromBodyMotion(Pose2(0.15, 0, 0),
                                      integrateDiffDriveMotion(intrinsic, layout, samples));
  };
}

/// The pairs of a 20 s run in the room with `options`.
inline std::vector<MotionPair> roomPairs(const CollectorOptions& options,
                                         CollectorStatistics* statistics)
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

}  // namespace test
}  // namespace odometry_calibration
