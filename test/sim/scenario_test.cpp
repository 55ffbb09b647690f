#include "odometry_calibration/sim/scenario.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/sim/pair_generator.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/alias_bomb.h"

namespace odometry_calibration {
namespace sim {
namespace {

const std::string kScenarios = std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/scenarios";

TEST(SimScenario, ShippedWorldsAreThePackagesConfigWorlds)
{
  EXPECT_TRUE(std::filesystem::is_regular_file(shippedWorldsDirectory() + "/office.yaml"));
  // A scenario naming a shipped world by its bare name loads with that folder.
  const Scenario scenario =
      loadScenarioYaml(kScenarios + "/diff_drive_office.yaml", shippedWorldsDirectory());
  EXPECT_EQ(std::filesystem::path(scenario.world_path).filename(), "office.yaml");
}

TEST(SimScenario, AnAliasBombIsRefusedNamingTheFile)
{
  // A scenario or a world whose aliases expand to a billion nodes: refused at once.
  const std::string path = testing::TempDir() + "/bomb_scenario.yaml";
  std::ofstream(path) << test::aliasBomb(9);
  try {
    sim::loadScenarioYaml(path, "");
    FAIL() << "an alias bomb accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path + ": YAML aliases expand to more than 100000"),
              std::string::npos)
        << error.what();
  }
  try {
    sim::parseWorldYaml(test::aliasBomb(9), "bomb_world.yaml");
    FAIL() << "an alias bomb accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()).rfind("bomb_world.yaml: YAML aliases expand to more", 0),
              0u)
        << error.what();
  }
  std::remove(path.c_str());
}

TEST(SimScenario, OverridesReplaceSeedAndDurationOnlyWhenGiven)
{
  const std::string path = kScenarios + "/pairs_ideal.yaml";
  const Scenario file = loadScenarioYaml(path, shippedWorldsDirectory());
  const Scenario kept = loadScenarioYaml(path, shippedWorldsDirectory(), ScenarioOverrides{});
  EXPECT_EQ(kept.seed, file.seed);
  EXPECT_EQ(kept.duration_s, file.duration_s);
  ScenarioOverrides overrides;
  overrides.seed = 0.0;
  overrides.duration_s = 12.5;
  const Scenario changed = loadScenarioYaml(path, shippedWorldsDirectory(), overrides);
  EXPECT_EQ(changed.seed, 0u);
  EXPECT_EQ(changed.duration_s, 12.5);
  overrides.duration_s = 0.0;  // 0 keeps the file's duration
  EXPECT_EQ(loadScenarioYaml(path, shippedWorldsDirectory(), overrides).duration_s,
            file.duration_s);
}

TEST(SimScenario, PairGeneratorTakesTheScenariosRobotAndRun)
{
  const Scenario scenario =
      loadScenarioYaml(kScenarios + "/pairs_ideal.yaml", shippedWorldsDirectory());
  PairGeneratorOptions given;
  given.interval_s = 0.7;
  given.translation_noise_m = 0.01;
  given.rotation_noise_rad = 0.02;
  const PairGeneratorOptions options = pairGeneratorOptions(scenario, given);
  EXPECT_EQ(options.robot.type, scenario.robot.type);
  EXPECT_EQ(options.robot.parameters, scenario.robot.parameters);
  EXPECT_EQ(options.T_base_sensor.x(), scenario.laser.T_base_laser.x());
  EXPECT_EQ(options.T_base_sensor.theta(), scenario.laser.T_base_laser.theta());
  EXPECT_EQ(options.motion.max_speed_mps, scenario.motion.max_speed_mps);
  EXPECT_EQ(options.encoder_rate_hz, scenario.encoders.rate_hz);
  EXPECT_EQ(options.duration_s, scenario.duration_s);
  EXPECT_EQ(options.seed, scenario.seed);
  EXPECT_EQ(options.interval_s, 0.7);
  EXPECT_EQ(options.translation_noise_m, 0.01);
  EXPECT_EQ(options.rotation_noise_rad, 0.02);
}

TEST(SimScenario, ChangesAreReadCheckedAndWrittenToTheTruth)
{
  const std::string path = "/tmp/odometry_calibration_scenario_changes_test.yaml";
  auto load = [&](const std::string& changes) {
    std::ofstream(path) << "robot: {type: diff_drive}\nchanges:\n" << changes;
    return loadScenarioYaml(path, shippedWorldsDirectory());
  };
  const Scenario s = load(
      "  - {at_s: 600, robot: {wheel_radius_right_m: 0.07623}}\n"
      "  - {at_s: 900, laser_yaw_change_rad: 0.01745}\n"
      "  - {at_s: 950, laser_x_change_m: 0.031, laser_y_change_m: -0.012, "
      "time_offset_change_s: 0.047}\n");
  ASSERT_EQ(s.changes.size(), 3u);
  EXPECT_DOUBLE_EQ(s.changes[0].at_s, 600.0);
  EXPECT_DOUBLE_EQ(s.changes[0].robot_parameters.at("wheel_radius_right_m"), 0.07623);
  EXPECT_DOUBLE_EQ(s.changes[1].laser_yaw_change_rad, 0.01745);
  EXPECT_DOUBLE_EQ(s.changes[1].laser_x_change_m, 0.0);
  EXPECT_DOUBLE_EQ(s.changes[2].laser_x_change_m, 0.031);
  EXPECT_DOUBLE_EQ(s.changes[2].laser_y_change_m, -0.012);
  EXPECT_DOUBLE_EQ(s.changes[2].time_offset_change_s, 0.047);
  const auto robot = makeRobot(s.robot);
  const std::string truth = scenarioTruthYaml(s, *robot);
  EXPECT_NE(truth.find("changes"), std::string::npos);
  EXPECT_NE(truth.find("0.07623"), std::string::npos);
  EXPECT_NE(truth.find("laser_x_change_m: 0.031"), std::string::npos) << truth;
  EXPECT_NE(truth.find("laser_y_change_m: -0.012"), std::string::npos) << truth;
  EXPECT_NE(truth.find("time_offset_change_s: 0.047"), std::string::npos) << truth;
  // A clock jumping back by more than an encoder period (50 Hz: 20 ms), a misspelt key: refused.
  try {
    load("  - {at_s: 10, time_offset_change_s: -0.03}\n");
    ADD_FAILURE() << "a clock going backwards was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("encoder period"), std::string::npos) << error.what();
  }
  EXPECT_NO_THROW(load("  - {at_s: 10, time_offset_change_s: -0.015}\n"));
  try {
    load("  - {at_s: 10, laser_z_change_m: 0.1}\n");
    ADD_FAILURE() << "an unknown change key was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("laser_z_change_m"), std::string::npos)
        << error.what();
  }
  // An unknown robot key, a change out of time order: refused, naming where.
  try {
    load("  - {at_s: 10, robot: {wheel_radius_middle_m: 0.1}}\n");
    ADD_FAILURE() << "an unknown key was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("changes[0]"), std::string::npos) << error.what();
  }
  EXPECT_THROW(load("  - {at_s: 10}\n  - {at_s: 5}\n"), std::exception);
  std::remove(path.c_str());
}

TEST(SimScenario, AChangeNamesItsLaserByIndexFrameOrTopic)
{
  const std::string path = "/tmp/odometry_calibration_scenario_laser_changes_test.yaml";
  auto load = [&](const std::string& changes) {
    std::ofstream(path) << "robot: {type: diff_drive}\nlasers:\n"
                           "  - {frame_id: laser_front, topic: /scan_front}\n"
                           "  - {frame_id: laser_rear, topic: /scan_rear, pose: {x: -0.3}}\n"
                           "changes:\n"
                        << changes;
    return loadScenarioYaml(path, shippedWorldsDirectory());
  };
  const Scenario s = load(
      "  - {at_s: 5, laser: laser_rear, laser_yaw_change_rad: 0.035}\n"
      "  - {at_s: 6, laser: /scan_front, laser_x_change_m: 0.01}\n"
      "  - {at_s: 7, laser: 1, laser_y_change_m: 0.02}\n"
      "  - {at_s: 8, laser_y_change_m: 0.03}\n");
  ASSERT_EQ(s.changes.size(), 4u);
  EXPECT_EQ(s.changes[0].laser_index, 1u);
  EXPECT_EQ(s.changes[1].laser_index, 0u);
  EXPECT_EQ(s.changes[2].laser_index, 1u);
  EXPECT_EQ(s.changes[3].laser_index, 0u);  // the first laser unless said
  const auto robot = makeRobot(s.robot);
  const std::string truth = scenarioTruthYaml(s, *robot);
  EXPECT_NE(truth.find("laser: 1"), std::string::npos) << truth;
  try {
    load("  - {at_s: 5, laser: laser_left, laser_yaw_change_rad: 0.035}\n");
    ADD_FAILURE() << "an unknown laser was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("'laser_left' is no laser"), std::string::npos)
        << error.what();
  }
  std::remove(path.c_str());
}

TEST(SimScenario, TheRangeRippleIsReadCheckedAndWrittenToTheTruthOnlyWhenOn)
{
  const std::string path = "/tmp/odometry_calibration_scenario_ripple_test.yaml";
  auto load = [&](const std::string& laser) {
    std::ofstream(path) << "robot: {type: diff_drive}\nlaser: {" << laser << "}\n";
    return loadScenarioYaml(path, shippedWorldsDirectory());
  };
  const Scenario off = load("rays: 100");
  EXPECT_EQ(off.laser.range_ripple_m, 0.0);
  EXPECT_EQ(scenarioTruthYaml(off, *makeRobot(off.robot)).find("range_ripple"), std::string::npos);
  const Scenario on = load("range_ripple_m: 0.002, range_ripple_period_rays: 25");
  EXPECT_DOUBLE_EQ(on.laser.range_ripple_m, 0.002);
  EXPECT_DOUBLE_EQ(on.laser.range_ripple_period_rays, 25.0);
  const std::string truth = scenarioTruthYaml(on, *makeRobot(on.robot));
  EXPECT_NE(truth.find("range_ripple_m: 0.002"), std::string::npos) << truth;
  EXPECT_NE(truth.find("range_ripple_period_rays: 25"), std::string::npos) << truth;
  for (const std::string bad : {"range_ripple_m: -0.001", "range_ripple_period_rays: 1"}) {
    try {
      load(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::exception& error) {
      EXPECT_NE(std::string(error.what()).find("range_ripple"), std::string::npos) << error.what();
    }
  }
  std::remove(path.c_str());
}

TEST(SimScenario, TheNoiseCorrelationIsReadCheckedAndWrittenToTheTruthOnlyWhenOn)
{
  const std::string path = "/tmp/odometry_calibration_scenario_correlation_test.yaml";
  auto load = [&](const std::string& laser) {
    std::ofstream(path) << "robot: {type: diff_drive}\nlaser: {" << laser << "}\n";
    return loadScenarioYaml(path, shippedWorldsDirectory());
  };
  const Scenario off = load("rays: 100");
  EXPECT_EQ(off.laser.range_noise_correlation, 0.0);
  EXPECT_EQ(scenarioTruthYaml(off, *makeRobot(off.robot)).find("range_noise_correlation"),
            std::string::npos);
  const Scenario on = load("range_noise_correlation: 0.5");
  EXPECT_DOUBLE_EQ(on.laser.range_noise_correlation, 0.5);
  const std::string truth = scenarioTruthYaml(on, *makeRobot(on.robot));
  EXPECT_NE(truth.find("range_noise_correlation: 0.5"), std::string::npos) << truth;
  for (const std::string bad : {"range_noise_correlation: -0.1", "range_noise_correlation: 0.99",
                                "range_noise_correlation: .nan"}) {
    try {
      load(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::exception& error) {
      EXPECT_NE(std::string(error.what()).find("range_noise_correlation"), std::string::npos)
          << error.what();
    }
  }
  // The shipped Mines-like scenario carries the real URG log's measured noise.
  const Scenario mines =
      loadScenarioYaml(kScenarios + "/mines_like.yaml", shippedWorldsDirectory());
  EXPECT_DOUBLE_EQ(mines.laser.range_noise_correlation, 0.5);
  EXPECT_DOUBLE_EQ(mines.laser.range_noise_m, 0.002);
  EXPECT_DOUBLE_EQ(mines.laser.range_noise_per_m, 0.003);
  std::remove(path.c_str());
}

TEST(SimScenario, ARunThatBarelyMovedIsTooLittle)
{
  Scenario scenario;
  scenario.duration_s = 100.0;
  scenario.motion.max_speed_mps = 0.5;  // 5 % of 50 m: 2.5 m
  SimulationSummary summary;
  summary.distance_m = 2.0;
  EXPECT_TRUE(droveTooLittle(scenario, summary));
  summary.distance_m = 3.0;
  EXPECT_FALSE(droveTooLittle(scenario, summary));
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
