#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/models/tricycle_kinematics.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {
namespace {

struct Recorder : SimulationSink
{
  std::vector<JointStateSample> joints;
  std::vector<ScanSample> scans;
  std::vector<TruthSample> truth;
  std::vector<BaseOdometrySample> base_odometry;
  void onJointState(const JointStateSample& s) override { joints.push_back(s); }
  void onBaseOdometry(const BaseOdometrySample& s) override { base_odometry.push_back(s); }
  void onScan(const ScanSample& s) override { scans.push_back(s); }
  void onTruth(const TruthSample& s) override { truth.push_back(s); }
};

World room()
{
  return parseWorldYaml("polygons:\n  - [[-5, -4], [5, -4], [5, 4], [-5, 4]]\n", "room");
}

Scenario smallScenario(const std::string& robot_type)
{
  Scenario s;
  s.duration_s = 10.0;
  s.robot.type = robot_type;
  s.laser.rays = 181;
  s.laser.fov_rad = M_PI;
  s.motion.max_speed_mps = 0.5;
  return s;
}

TEST(Simulator, MessageCountsRatesAndTimeOffset)
{
  Scenario s = smallScenario("diff_drive");
  s.encoders.rate_hz = 40.0;
  s.laser.rate_hz = 8.0;
  s.encoders.time_offset_s = -0.15;
  const World world = room();
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  const SimulationSummary summary = simulate(s, world, *robot, recorder);
  EXPECT_EQ(recorder.joints.size(), 401u);  // t = 0, 0.025, ..., 10
  EXPECT_EQ(recorder.scans.size(), 81u);
  EXPECT_EQ(summary.joint_states, 401u);
  EXPECT_GT(summary.distance_m, 1.0);  // it really drove
  for (std::size_t k = 1; k < recorder.joints.size(); ++k) {
    EXPECT_NEAR(recorder.joints[k].stamp_s - recorder.joints[k - 1].stamp_s, 0.025, 1e-9);
  }
  EXPECT_NEAR(recorder.scans[1].stamp_s - recorder.scans[0].stamp_s, 0.125, 1e-9);
  EXPECT_NEAR(recorder.joints[10].stamp_s, recorder.truth[10].stamp_s - 0.15, 1e-12);
  EXPECT_EQ(recorder.scans[0].ranges.size(), 181u);
}

TEST(Simulator, BaseOdometryReportsItsScaleErrorsAtEveryEncoderInstant)
{
  Scenario s = smallScenario("diff_drive");
  s.encoders.output = "odometry";
  s.encoders.time_offset_s = 0.05;
  s.encoders.odometry_translation_error = 0.03;
  s.encoders.odometry_rotation_error = -0.02;
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, room(), *robot, recorder);
  ASSERT_EQ(recorder.base_odometry.size(), recorder.joints.size());  // besides the JointState
  // Instant by instant: the true step with its translation x 1.03 and its rotation x 0.98.
  double travel_m = 0.0, turn_rad = 0.0;
  for (std::size_t k = 1; k < recorder.truth.size(); ++k) {
    const Pose2 truth = between(recorder.truth[k - 1].T_world_base, recorder.truth[k].T_world_base);
    const Pose2 reported =
        between(recorder.base_odometry[k - 1].T_odom_base, recorder.base_odometry[k].T_odom_base);
    EXPECT_NEAR(reported.x(), 1.03 * truth.x(), 1e-9);
    EXPECT_NEAR(reported.y(), 1.03 * truth.y(), 1e-9);
    EXPECT_NEAR(reported.theta(), 0.98 * truth.theta(), 1e-9);
    EXPECT_NEAR(recorder.base_odometry[k].stamp_s, recorder.joints[k].stamp_s, 1e-12);
    travel_m += std::hypot(truth.x(), truth.y());
    turn_rad += std::abs(truth.theta());
  }
  EXPECT_GT(travel_m, 1.0);  // it drove and turned
  EXPECT_GT(turn_rad, 0.5);
  EXPECT_NEAR(recorder.base_odometry[3].twist.omega_radps,
              0.98 * recorder.truth[3].twist.omega_radps, 1e-12);
}

TEST(Simulator, ExtraLasersScanAtTheirOwnRatesPosesAndClocks)
{
  Scenario one = smallScenario("diff_drive");
  Scenario two = one;
  LaserOptions rear = two.laser;
  rear.T_base_laser = Pose2(-0.3, 0.02, M_PI + 0.03);
  rear.rate_hz = 15.0;
  rear.rays = 91;
  rear.time_offset_s = 0.05;
  rear.topic = "/scan_rear";
  rear.frame_id = "laser_rear";
  two.extra_lasers.push_back(rear);
  const World world = room();
  const auto robot = makeRobot(one.robot);
  Recorder alone, both;
  simulate(one, world, *robot, alone);
  simulate(two, world, *robot, both);
  std::vector<ScanSample> first, second;
  for (const ScanSample& scan : both.scans)
    (scan.laser_index == 0 ? first : second).push_back(scan);
  // The first laser reads what it read alone: its random streams are its own; only the
  // integration steps, split at the rear laser's instants too, move the path by micrometres.
  ASSERT_EQ(first.size(), alone.scans.size());
  double largest_m = 0.0;
  for (std::size_t k = 0; k < first.size(); ++k) {
    EXPECT_EQ(first[k].stamp_s, alone.scans[k].stamp_s);
    ASSERT_EQ(first[k].ranges.size(), alone.scans[k].ranges.size());
    for (std::size_t i = 0; i < first[k].ranges.size(); ++i) {
      if (std::isfinite(first[k].ranges[i]) && std::isfinite(alone.scans[k].ranges[i]))
        largest_m =
            std::max(largest_m, double(std::abs(first[k].ranges[i] - alone.scans[k].ranges[i])));
    }
  }
  EXPECT_LT(largest_m, 1e-3);
  std::printf("largest range change of the first laser: %.3g m\n", largest_m);
  // The rear laser: 15 Hz over 10 s, its stamps 0.05 s after the true time; its period rounds
  // to 66666667 ns, so the scan due at 10 s comes 50 ns after the end: 150 scans.
  ASSERT_EQ(second.size(), 150u);
  EXPECT_EQ(second[0].ranges.size(), 91u);
  EXPECT_NEAR(second[0].stamp_s, 0.05, 1e-12);
  EXPECT_NEAR(second[3].stamp_s - second[0].stamp_s, 0.2, 1e-8);  // 3 x 66666667 ns
  // Its rays start from its own pose: at t = 0 the robot stands at the origin facing +x, so
  // the rear laser's middle ray (pointing backwards, 0.03 rad off) reads the wall behind it,
  // 5 - 0.3 m away along the x axis (room wall at x = -5).
  const double middle = second[0].ranges[45];
  EXPECT_NEAR(middle * std::cos(0.03), 5.0 - 0.3, 0.05);
}

TEST(Simulator, IntegratingTheEncodersReproducesTheTruth)
{
  // Ideal diff drive: the kinematics applied to tick increments must follow the truth up to
  // the tick quantisation.
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 20.0;
  s.encoders.initial_ticks = 4294967296.0 - 3000.0;  // wraps early
  const World world = room();
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, world, *robot, recorder);
  EncoderDecoder decoder({{"l", EncoderKind::kIncremental, 4294967296.0, 0.0},
                          {"r", EncoderKind::kIncremental, 4294967296.0, 0.0}});
  const double metres_per_tick = 2.0 * M_PI * 0.077 / 2000.0;
  Pose2 pose = s.start_pose;
  Eigen::VectorXd previous =
      decoder.decode(Eigen::Map<const Eigen::VectorXd>(recorder.joints[0].positions.data(), 2));
  double worst_m = 0.0;
  for (std::size_t k = 1; k < recorder.joints.size(); ++k) {
    const Eigen::VectorXd now =
        decoder.decode(Eigen::Map<const Eigen::VectorXd>(recorder.joints[k].positions.data(), 2));
    const double left = (now(0) - previous(0)) * metres_per_tick;
    const double right = (now(1) - previous(1)) * metres_per_tick;
    previous = now;
    const double dt = 0.02;
    pose = pose * integrateTwist({(left + right) / 2 / dt, 0.0, (right - left) / 0.33 / dt}, dt);
    const Pose2 error = between(recorder.truth[k].T_world_base, pose);
    worst_m = std::max(worst_m, std::hypot(error.x(), error.y()));
  }
  EXPECT_LT(worst_m, 0.02);
  EXPECT_GT(
      std::hypot(recorder.truth.back().T_world_base.x(), recorder.truth.back().T_world_base.y()) +
          std::abs(recorder.truth.back().T_world_base.theta()),
      0.3);  // the robot did move away
}

TEST(Simulator, TricycleEncodersFollowTheSeedModel)
{
  Scenario s = smallScenario("tricycle");
  s.motion.max_turn_rate_radps = 0.4;
  s.motion.clearance_m = 0.1;
  s.start_pose = Pose2(-1.0, 0.0, 0.0);
  const World world =
      parseWorldYaml("polygons:\n  - [[-15, -10], [15, -10], [15, 10], [-15, 10]]\n", "hall");
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, world, *robot, recorder);
  // Decode like the real log: steering absolute (8192), traction incremental uint32.
  EncoderDecoder decoder({{"steering", EncoderKind::kAbsolute, 0.0, 8192.0},
                          {"traction", EncoderKind::kIncremental, 4294967296.0, 0.0}});
  std::vector<EncoderSample> samples;
  for (const auto& j : recorder.joints) {
    samples.push_back({j.stamp_s, decoder.decode(Eigen::Vector2d(j.positions[0], j.positions[1]))});
  }
  const double kinematic[4] = {0.56, 0.0106, 1.54, -0.06};  // the tricycle's defaults
  const TricycleEncoderLayout layout;
  const Pose2 predicted = s.start_pose * integrateTricycleMotion(kinematic, layout, samples);
  const Pose2 error = between(recorder.truth.back().T_world_base, predicted);
  EXPECT_LT(std::hypot(error.x(), error.y()), 0.05);
  EXPECT_LT(std::abs(error.theta()), 0.01);
}

TEST(Simulator, RayCastRangeAtAKnownPoseMatchesTheGeometry)
{
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 0.5;
  s.motion.type = "scripted";
  s.motion.script = {{10.0, Twist2()}};  // stand still
  s.start_pose = Pose2(1.0, -1.0, 0.3);
  s.laser.T_base_laser = Pose2(0.2, 0.1, -0.3);  // laser looks along world x
  s.laser.range_noise_m = 0.0;
  const World world = room();
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, world, *robot, recorder);
  const Pose2 T_world_laser = s.start_pose * s.laser.T_base_laser;
  ASSERT_NEAR(T_world_laser.theta(), 0.0, 1e-12);
  const ScanSample& scan = recorder.scans.front();
  const std::size_t forward = 90;  // 181 rays over 180 degrees: ray 90 looks straight ahead
  EXPECT_NEAR(scan.angle_min_rad + forward * scan.angle_increment_rad, 0.0, 1e-6);
  EXPECT_NEAR(scan.ranges[forward], 5.0 - T_world_laser.x(), 1e-5);  // east wall x = 5
  EXPECT_NEAR(scan.ranges[180], 4.0 - T_world_laser.y(), 1e-5);      // north wall, +90 deg
  EXPECT_NEAR(scan.ranges[0], 4.0 + T_world_laser.y(), 1e-5);        // south wall, -90 deg
}

TEST(Simulator, CounterWrapsWhereConfigured)
{
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 5.0;
  s.motion.type = "scripted";
  s.motion.script = {{5.0, Twist2{0.2, 0.0, 0.0}}};  // straight ahead
  s.motion.max_acceleration_mps2 = 0.0;              // at full speed from the start
  s.encoders.counter_bits = 16;
  s.encoders.initial_ticks = 65536 - 500;
  const World world = room();
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  const SimulationSummary summary = simulate(s, world, *robot, recorder);
  EXPECT_EQ(summary.counter_wraps, 2u);  // both wheels, once
  // 500 ticks of 2000 per turn at 0.2 m/s: 0.25 turn = 0.1210 m, reached after 0.605 s.
  const double wrap_time_s = 0.25 * 2.0 * M_PI * 0.077 / 0.2;
  for (const auto& sample : recorder.joints) {
    if (sample.stamp_s < wrap_time_s - 0.02) {
      EXPECT_GE(sample.positions[0], 65036.0) << sample.stamp_s;
    } else if (sample.stamp_s > wrap_time_s + 0.02) {
      EXPECT_LT(sample.positions[0], 65036.0) << sample.stamp_s;
    }
    EXPECT_LT(sample.positions[0], 65536.0);
  }
}

TEST(Simulator, EncoderReadingQuantisesAndWraps)
{
  EncoderOptions options;
  options.counter_bits = 8;
  const JointEncoderSpec wheel{"w", EncoderKind::kIncremental, 100};
  EXPECT_EQ(encoderReading(wheel, options, 2.0 * M_PI * 0.999), 99.0);
  EXPECT_EQ(encoderReading(wheel, options, 2.0 * M_PI * 2.6), 260.0 - 256.0);
  EXPECT_EQ(encoderReading(wheel, options, -2.0 * M_PI * 0.011), 256.0 - 2.0);
  const JointEncoderSpec steering{"s", EncoderKind::kAbsolute, 8192};
  EXPECT_EQ(encoderReading(steering, options, -0.1 * 2.0 * M_PI), 8192.0 - 819.0);
  options.output_ticks = false;
  EXPECT_NEAR(encoderReading(steering, options, -0.1 * 2.0 * M_PI), -819.0 * 2.0 * M_PI / 8192,
              1e-12);
}

TEST(Simulator, RandomDriveLeavesOutTheMotionsAskedFor)
{
  // The default random drive turns both ways and on the spot; each option removes its motion.
  auto run = [](bool left, bool right, bool in_place) {
    Scenario s = smallScenario("diff_drive");
    s.duration_s = 120.0;
    s.motion.left_turns = left;
    s.motion.right_turns = right;
    s.motion.turning_in_place = in_place;
    const auto robot = makeRobot(s.robot);
    Recorder recorder;
    simulate(s, room(), *robot, recorder);
    double most_left = 0.0, most_right = 0.0, spot = 0.0;
    for (const TruthSample& t : recorder.truth) {
      most_left = std::max(most_left, t.twist.omega_radps);
      most_right = std::min(most_right, t.twist.omega_radps);
      if (std::abs(t.twist.vx_mps) < 0.01 && std::abs(t.twist.omega_radps) > 0.3)
        spot += 1.0;
    }
    return std::array<double, 3>{most_left, most_right, spot};
  };
  const auto all = run(true, true, true);
  EXPECT_GT(all[0], 0.3);
  EXPECT_LT(all[1], -0.3);
  EXPECT_GT(all[2], 50.0);  // samples turning on the spot
  const auto no_left = run(false, true, true);
  EXPECT_LE(no_left[0], 1e-9);
  EXPECT_LT(no_left[1], -0.3);
  const auto no_right = run(true, false, true);
  EXPECT_GE(no_right[1], -1e-9);
  EXPECT_GT(no_right[0], 0.3);
  const auto no_spot = run(true, true, false);
  // (only the instants an arc reverses through zero speed remain)
  EXPECT_LT(no_spot[2], 0.05 * all[2]) << no_spot[2] << " of " << all[2];
  EXPECT_GT(no_spot[0], 0.3);
}

TEST(Simulator, ParameterChangesTakeEffectAtTheirTime)
{
  // Straight ahead for 8 s; at 4 s the right wheel shrinks by 1 % and the laser yaws by 1 deg.
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 8.0;
  s.start_pose = Pose2(-3.0, 0.0, 0.0);
  s.motion.type = "scripted";
  s.motion.script = {{8.0, {0.5, 0.0, 0.0}}};
  ParameterChange change;
  change.at_s = 4.0;
  change.robot_parameters["wheel_radius_right_m"] = 0.99 * 0.077;
  change.laser_yaw_change_rad = M_PI / 180.0;
  s.changes = {change};
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, room(), *robot, recorder);
  ASSERT_GT(recorder.truth.size(), 300u);
  for (const TruthSample& t : recorder.truth) {
    if (t.stamp_s < 4.0) {
      // The unchanged robot drives straight; the laser keeps its mounting.
      EXPECT_NEAR(t.T_world_base.theta(), 0.0, 1e-9) << t.stamp_s;
      EXPECT_NEAR(t.T_base_laser.theta(), 0.0, 1e-12);
    } else {
      EXPECT_NEAR(t.T_base_laser.theta(), M_PI / 180.0, 1e-12) << t.stamp_s;
    }
  }
  // The controller keeps the robot straight: the smaller right wheel turns faster, 1 / 0.99
  // times the left one (encoders in ticks; samples at 50 Hz, so index 100 is 2 s).
  auto ratio = [&](std::size_t from, std::size_t to) {
    const auto& a = recorder.joints[from].positions;
    const auto& b = recorder.joints[to].positions;
    return (b[1] - a[1]) / (b[0] - a[0]);
  };
  EXPECT_NEAR(ratio(100, 195), 1.0, 1e-3);
  EXPECT_NEAR(ratio(255, 395), 1.0 / 0.99, 1e-3);
  EXPECT_NEAR(recorder.truth.back().T_world_base.theta(), 0.0, 1e-9);
  // Not in time order: rejected.
  s.changes = {change, change};
  s.changes[1].at_s = 1.0;
  EXPECT_THROW(simulate(s, room(), *robot, recorder), std::invalid_argument);
}

TEST(Simulator, LaserShiftsAndClockJumpsTakeEffectAtTheirTime)
{
  // Straight ahead for 6 s; at 2 s the laser moves 3 cm forward and 1 cm left, at 4 s it yaws
  // by 1.5 deg and the encoders' clock jumps 40 ms ahead; the changes add up.
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 6.0;
  s.start_pose = Pose2(-3.0, 0.0, 0.0);
  s.motion.type = "scripted";
  s.motion.script = {{6.0, {0.5, 0.0, 0.0}}};
  s.encoders.time_offset_s = 0.01;
  const Pose2 mounting = s.laser.T_base_laser;
  ParameterChange shift, turn;
  shift.at_s = 2.0;
  shift.laser_x_change_m = 0.03;
  shift.laser_y_change_m = 0.01;
  turn.at_s = 4.0;
  turn.laser_yaw_change_rad = 1.5 * M_PI / 180.0;
  turn.time_offset_change_s = 0.04;
  s.changes = {shift, turn};
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  simulate(s, room(), *robot, recorder);
  ASSERT_EQ(recorder.truth.size(), recorder.joints.size());
  for (std::size_t i = 0; i < recorder.truth.size(); ++i) {
    const TruthSample& t = recorder.truth[i];
    const bool shifted = t.stamp_s >= 2.0 - 1e-9, turned = t.stamp_s >= 4.0 - 1e-9;
    EXPECT_NEAR(t.T_base_laser.x(), mounting.x() + (shifted ? 0.03 : 0.0), 1e-12) << t.stamp_s;
    EXPECT_NEAR(t.T_base_laser.y(), mounting.y() + (shifted ? 0.01 : 0.0), 1e-12) << t.stamp_s;
    EXPECT_NEAR(t.T_base_laser.theta(), mounting.theta() + (turned ? 1.5 * M_PI / 180.0 : 0.0),
                1e-12)
        << t.stamp_s;
    EXPECT_NEAR(recorder.joints[i].stamp_s - t.stamp_s, turned ? 0.05 : 0.01, 1e-9) << t.stamp_s;
  }
}

TEST(Simulator, AChangeMovesTheLaserItNamesOnly)
{
  // Standing at the origin facing +x with a rear laser (issue 35); at 1 s the rear laser (index
  // 1) yaws by 0.2 rad. The front laser reads what it read without the change; the rear one
  // the same until 1 s, then its middle ray meets the wall behind (x = -5) 0.2 rad further round.
  Scenario s = smallScenario("diff_drive");
  s.duration_s = 2.0;
  s.motion.type = "scripted";
  s.motion.script = {{2.0, {0.0, 0.0, 0.0}}};
  LaserOptions rear = s.laser;
  rear.T_base_laser = Pose2(-0.3, 0.02, M_PI + 0.03);
  rear.topic = "/scan_rear";
  rear.frame_id = "laser_rear";
  s.extra_lasers.push_back(rear);
  Scenario changed = s;
  ParameterChange turn;
  turn.at_s = 1.0;
  turn.laser_index = 1;
  turn.laser_yaw_change_rad = 0.2;
  changed.changes = {turn};
  const auto robot = makeRobot(s.robot);
  Recorder before, after;
  simulate(s, room(), *robot, before);
  simulate(changed, room(), *robot, after);
  ASSERT_EQ(before.scans.size(), after.scans.size());
  std::size_t rear_after_change = 0;
  for (std::size_t k = 0; k < after.scans.size(); ++k) {
    const ScanSample& scan = after.scans[k];
    const bool moved = scan.laser_index == 1 && scan.stamp_s >= 1.0;
    EXPECT_EQ(scan.ranges == before.scans[k].ranges, !moved) << k;
    if (!moved || scan.laser_index != 1)
      continue;
    // The middle ray from (-0.3, 0.02) at pi + 0.23 reaches x = -5 after 4.7 / cos(0.23).
    const double middle = scan.ranges[90];
    EXPECT_NEAR(middle, 4.7 / std::cos(0.23), 0.05) << scan.stamp_s;
    ++rear_after_change;
  }
  EXPECT_EQ(rear_after_change, 11u);  // 10 Hz, stamps 1.0 .. 2.0
  // The truth's mounting is the first laser's: unchanged.
  for (const TruthSample& t : after.truth)
    EXPECT_EQ(t.T_base_laser.theta(), s.laser.T_base_laser.theta());
  // A change of a laser the scenario lacks: refused, naming it.
  changed.changes[0].laser_index = 2;
  try {
    validate(changed);
    ADD_FAILURE() << "a change of a third laser was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("laser 2 does not exist"), std::string::npos)
        << error.what();
  }
}

TEST(Simulator, RejectsAStartInsideTheFurnitureAndWrongJointNames)
{
  Scenario s = smallScenario("diff_drive");
  s.start_pose = Pose2(4.9, 0.0, 0.0);
  const World world = room();
  const auto robot = makeRobot(s.robot);
  Recorder recorder;
  EXPECT_THROW(simulate(s, world, *robot, recorder), std::invalid_argument);
  s.start_pose = Pose2(30.0, 0.0, 0.0);  // outside the building
  EXPECT_THROW(simulate(s, world, *robot, recorder), std::invalid_argument);
  const World furnished = parseWorldYaml(
      "polygons: [[[-5, -4], [5, -4], [5, 4], [-5, 4]]]\nboxes: [{center: [2, 2], size: [2, 2]}]\n",
      "room");
  s.start_pose = Pose2(2.0, 2.0, 0.0);  // in the middle of a table, far from its edges
  EXPECT_THROW(simulate(s, furnished, *robot, recorder), std::invalid_argument);
  s.start_pose = Pose2();
  s.encoders.joint_names = {"only_one"};
  EXPECT_THROW(simulate(s, world, *robot, recorder), std::invalid_argument);
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
