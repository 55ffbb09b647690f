// The gyro's fit (gyro_fit.h) on the simulator's IMU: scale, bias and clock of a gyro against the
// true rotation of keyframe pairs measured with a laser-like noise, the tilted mounting undone,
// and the refusals (too few readings, a robot that does not turn).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"
#include "support/acceptance_imu.h"

namespace odometry_calibration {
namespace {

struct Recorder : sim::SimulationSink
{
  std::vector<sim::TruthSample> truth;
  std::vector<sim::ImuSample> imu;
  void onJointState(const sim::JointStateSample&) override {}
  void onScan(const sim::ScanSample&) override {}
  void onTruth(const sim::TruthSample& s) override { truth.push_back(s); }
  void onImu(const sim::ImuSample& s) override { imu.push_back(s); }
};

/// A 180 s random drive with the acceptance's gyro: 1.5 % scale, 0.01 rad/s bias walking
/// 1e-6 rad/s/sqrt(s) (1.3e-5 rad/s over the run), 2 mrad/s noise, its clock 20 ms late.
sim::Scenario gyroScenario(unsigned seed)
{
  sim::Scenario s;
  s.seed = seed;
  s.duration_s = 180.0;
  s.robot.type = "diff_drive";
  s.laser.rays = 31;
  s.laser.fov_rad = M_PI;
  s.motion.max_speed_mps = 0.5;
  s.motion.max_turn_rate_radps = 1.0;
  s.imu = test::acceptanceImu();
  return s;
}

Recorder run(const sim::Scenario& scenario)
{
  const sim::World world =
      sim::parseWorldYaml("polygons:\n  - [[-8, -6], [8, -6], [8, 6], [-8, 6]]\n", "room");
  const auto robot = sim::makeRobot(scenario.robot);
  Recorder recorder;
  sim::simulate(scenario, world, *robot, recorder);
  return recorder;
}

/// Keyframe pairs every `every` truth samples (50 Hz): the true heading change with a laser's
/// 0.5 mrad noise (a scan matcher's), on the true clock (the pairs' own offset 0).
std::vector<MotionPair> pairsFromTruth(const std::vector<sim::TruthSample>& truth, int every)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 5e-4);
  std::vector<MotionPair> pairs;
  for (std::size_t k = 0; k + every < truth.size(); k += every) {
    MotionPair pair;
    pair.start_stamp_s = truth[k].stamp_s;
    pair.end_stamp_s = truth[k + every].stamp_s;
    pair.sensor_motion = truth[k].T_world_base.inverse() * truth[k + every].T_world_base;
    pair.sensor_motion = Pose2(0.0, 0.0, pair.sensor_motion.theta() + noise(rng));
    pair.covariance = Eigen::Matrix3d::Identity() * 2.5e-7;
    pairs.push_back(pair);
  }
  return pairs;
}

TEST(GyroFit, ScaleBiasAndClockOfTheSimulatedGyro)
{
  const Recorder data = run(gyroScenario(4701));
  ASSERT_NEAR(static_cast<double>(data.imu.size()), 100.0 * 180.0, 2.0);
  const GyroFit fit =
      fitGyro(pairsFromTruth(data.truth, 25), 0.0, test::yawRates(data.imu, 0, 0), {});
  ASSERT_TRUE(fit.fitted) << fit.problem;
  EXPECT_NEAR(fit.scale.value, 1.015, 0.001 * 1.015);
  EXPECT_NEAR(fit.bias.value, 0.01, 1e-4);
  // Its clock 20 ms late: the encoders' values at the gyro's stamp - 20 ms.
  EXPECT_NEAR(fit.time_offset.value, -0.02, 0.002);
  EXPECT_GT(fit.scale.sigma, 0.0);
  EXPECT_LT(fit.scale.sigma, 0.001);
  EXPECT_LT(fit.bias.sigma, 1e-4);
  EXPECT_GT(fit.pairs, 300u);
}

TEST(GyroFit, ATiltedImuIsLevelledByItsMounting)
{
  sim::Scenario scenario = gyroScenario(4702);
  scenario.imu.roll_rad = 0.3;
  scenario.imu.pitch_rad = -0.2;
  scenario.imu.bias_rad_s = 0.0;
  const Recorder data = run(scenario);
  const std::vector<MotionPair> pairs = pairsFromTruth(data.truth, 25);
  const GyroFit levelled = fitGyro(pairs, 0.0, test::yawRates(data.imu, 0.3, -0.2), {});
  const GyroFit tilted = fitGyro(pairs, 0.0, test::yawRates(data.imu, 0.0, 0.0), {});
  ASSERT_TRUE(levelled.fitted && tilted.fitted);
  EXPECT_NEAR(levelled.scale.value, 1.015, 0.001);
  // Read as if level, the z axis sees cos(0.3) cos(0.2) of the turn.
  EXPECT_NEAR(tilted.scale.value, 1.015 * std::cos(0.3) * std::cos(0.2), 0.002);
}

TEST(GyroFit, RefusesTooFewReadingsAndAStraightDrive)
{
  const Recorder data = run(gyroScenario(4703));
  const std::vector<MotionPair> pairs = pairsFromTruth(data.truth, 25);
  std::vector<GyroSample> short_track = test::yawRates(data.imu, 0, 0);
  short_track.resize(300);  // 3 s of readings
  const GyroFit few = fitGyro(pairs, 0.0, short_track, {});
  EXPECT_FALSE(few.fitted);
  EXPECT_NE(few.problem.find("pairs lie inside the gyro's 300 readings"), std::string::npos)
      << few.problem;
  std::vector<MotionPair> straight = pairs;
  for (MotionPair& pair : straight)
    pair.sensor_motion = Pose2(0.0, 0.0, 0.0);
  const GyroFit none = fitGyro(straight, 0.0, test::yawRates(data.imu, 0, 0), {});
  EXPECT_FALSE(none.fitted);
  EXPECT_NE(none.problem.find("barely turns"), std::string::npos) << none.problem;
  std::vector<GyroSample> bad = test::yawRates(data.imu, 0, 0);
  bad[500].yaw_rate_rad_s = std::nan("");
  bad[600].stamp_s = bad[599].stamp_s - 1.0;  // time going backwards: left out
  EXPECT_TRUE(fitGyro(pairs, 0.0, bad, {}).fitted);
}

}  // namespace
}  // namespace odometry_calibration
