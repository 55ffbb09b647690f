#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"

namespace odometry_calibration {
namespace {

const std::string kWorlds = std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds";

/// A fresh directory, removed with everything in it when the object goes away.
class Scratch
{
public:
  Scratch()
  {
    char pattern[] = "/tmp/sim_bag_test.XXXXXX";
    const char* directory = mkdtemp(pattern);
    if (directory == nullptr)
      throw std::runtime_error("mkdtemp failed");
    path_ = directory;
  }
  ~Scratch() { std::filesystem::remove_all(path_); }
  operator const std::string&() const { return path_; }

private:
  std::string path_;
};

std::string writeScenario(const std::string& directory, const std::string& body)
{
  const std::string path = directory + "/scenario.yaml";
  std::ofstream(path) << body;
  return path;
}

std::string contents(const std::string& path)
{
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), {});
}

const char* kScenario =
    "name: small\nseed: 4\nduration_s: 3.0\nworld: office\n"
    "robot: {type: diff_drive, wheel_separation_m: 0.31}\n"
    "laser: {rays: 360, rate_hz: 10.0, frame_id: front_laser, topic: /front/scan}\n"
    "encoders: {rate_hz: 20.0, joint_names: [wheel_l, wheel_r], time_offset_s: 0.05}\n";

TEST(SimBag, WritesTheTopicsCountsAndFrames)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  const sim::Scenario scenario =
      sim::loadScenarioYaml(writeScenario(directory, kScenario), kWorlds);
  const std::string bag_path = directory + "/small.bag";
  const auto summary = simulateToBag(scenario, bag_path, directory + "/truth.yaml");
  EXPECT_EQ(summary.joint_states, 61u);
  EXPECT_EQ(summary.scans, 31u);

  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  std::size_t joint_states = 0, scans = 0, truth = 0;
  ros::Time previous_scan;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/joint_states") {
      const auto js = m.instantiate<sensor_msgs::JointState>();
      ASSERT_TRUE(js);
      ASSERT_EQ(js->name.size(), 2u);
      EXPECT_EQ(js->name[0], "wheel_l");
      EXPECT_EQ(js->position.size(), 2u);
      EXPECT_EQ(m.getTime(), js->header.stamp);
      ++joint_states;
    } else if (m.getTopic() == "/front/scan") {
      const auto scan = m.instantiate<sensor_msgs::LaserScan>();
      ASSERT_TRUE(scan);
      EXPECT_EQ(scan->header.frame_id, "front_laser");
      EXPECT_EQ(scan->ranges.size(), 360u);
      EXPECT_NEAR(scan->angle_max - scan->angle_min, 4.71238898, 1e-5);
      if (scans > 0) {
        EXPECT_NEAR((scan->header.stamp - previous_scan).toSec(), 0.1, 1e-9);
      }
      previous_scan = scan->header.stamp;
      ++scans;
    } else if (m.getTopic() == "/ground_truth/odom") {
      const auto odom = m.instantiate<nav_msgs::Odometry>();
      ASSERT_TRUE(odom);
      EXPECT_EQ(odom->header.frame_id, "sim_world");
      EXPECT_EQ(odom->child_frame_id, "sim_base_link");
      ++truth;
    }
  }
  EXPECT_EQ(joint_states, 61u);
  EXPECT_EQ(scans, 31u);
  EXPECT_EQ(truth, 61u);
  EXPECT_NEAR(rosbag::View(bag).getBeginTime().toSec(), 1700000000.0, 1e-6);

  const YAML::Node truth_yaml = YAML::LoadFile(directory + "/truth.yaml");
  EXPECT_DOUBLE_EQ(truth_yaml["robot"]["wheel_separation_m"].as<double>(), 0.31);
  EXPECT_EQ(truth_yaml["joints"][1]["name"].as<std::string>(), "wheel_r");
  EXPECT_DOUBLE_EQ(truth_yaml["encoders"]["time_offset_s"].as<double>(), 0.05);
}

TEST(SimBag, SameSeedSameBytesOtherSeedOtherBytes)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  sim::Scenario scenario = sim::loadScenarioYaml(writeScenario(directory, kScenario), kWorlds);
  simulateToBag(scenario, directory + "/a.bag", "");
  simulateToBag(scenario, directory + "/b.bag", "");
  scenario.seed = 5;
  simulateToBag(scenario, directory + "/c.bag", "");
  const std::string a = contents(directory + "/a.bag");
  EXPECT_GT(a.size(), 100000u);
  EXPECT_EQ(a, contents(directory + "/b.bag"));
  EXPECT_NE(a, contents(directory + "/c.bag"));
}

TEST(SimBag, OneLaserListedUnderLasersGivesTheSameBytes)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  const sim::Scenario as_laser =
      sim::loadScenarioYaml(writeScenario(directory, kScenario), kWorlds);
  std::string listed = kScenario;
  listed.replace(listed.find("laser: {"), 8, "lasers:\n  - {");
  const sim::Scenario as_list = sim::loadScenarioYaml(writeScenario(directory, listed), kWorlds);
  ASSERT_TRUE(as_list.extra_lasers.empty());
  simulateToBag(as_laser, directory + "/a.bag", directory + "/a.yaml");
  simulateToBag(as_list, directory + "/b.bag", directory + "/b.yaml");
  EXPECT_EQ(contents(directory + "/a.bag"), contents(directory + "/b.bag"));
  EXPECT_EQ(contents(directory + "/a.yaml"), contents(directory + "/b.yaml"));
}

TEST(SimBag, FrontAndRearLasersOnTheirTopicsWithTheirTruth)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  sim::Scenario scenario = sim::loadScenarioYaml(
      std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/scenarios/diff_drive_front_rear.yaml",
      kWorlds);
  ASSERT_EQ(scenario.extra_lasers.size(), 1u);
  scenario.duration_s = 2.0;
  scenario.extra_lasers[0].time_offset_s = 0.05;
  const auto summary = simulateToBag(scenario, directory + "/fr.bag", directory + "/fr.yaml");
  // 10 Hz and 15 Hz over [0, 2] s (the 15 Hz period rounds up to 66666667 ns: the scan due at
  // 2 s falls after the end).
  EXPECT_EQ(summary.scans, 21u + 30u);
  rosbag::Bag bag(directory + "/fr.bag", rosbag::bagmode::Read);
  std::map<std::string, std::size_t> scans;
  std::map<std::string, std::string> frames;
  double first_rear_stamp_s = -1.0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (const auto scan = m.instantiate<sensor_msgs::LaserScan>()) {
      ++scans[m.getTopic()];
      frames[m.getTopic()] = scan->header.frame_id;
      EXPECT_EQ(scan->header.seq + 1, scans[m.getTopic()]);  // each laser counts its own
      if (m.getTopic() == "/scan_rear" && first_rear_stamp_s < 0.0)
        first_rear_stamp_s = scan->header.stamp.toSec() - scenario.start_time_s;
    }
  }
  EXPECT_EQ(scans["/scan_front"], 21u);
  EXPECT_EQ(scans["/scan_rear"], 30u);
  EXPECT_EQ(frames["/scan_rear"], "laser_rear");
  EXPECT_NEAR(first_rear_stamp_s, 0.05, 1e-6);  // its own clock
  const YAML::Node truth = YAML::LoadFile(directory + "/fr.yaml");
  ASSERT_EQ(truth["extra_lasers"].size(), 1u);
  EXPECT_DOUBLE_EQ(truth["extra_lasers"][0]["T_base_laser"]["x"].as<double>(), -0.3);
  EXPECT_DOUBLE_EQ(truth["extra_lasers"][0]["laser"]["time_offset_s"].as<double>(), 0.05);
  EXPECT_EQ(truth["extra_lasers"][0]["laser"]["topic"].as<std::string>(), "/scan_rear");
  EXPECT_DOUBLE_EQ(truth["T_base_laser"]["x"].as<double>(), 0.3);
}

TEST(SimBag, ScenarioErrorsNameTheKey)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  auto message = [&](const std::string& body) -> std::string {
    try {
      sim::loadScenarioYaml(writeScenario(directory, body), kWorlds);
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(message("durations: 3\n").find("unknown key 'durations'"), std::string::npos);
  EXPECT_NE(message("laser: {rayz: 3}\n").find("rayz"), std::string::npos);
  EXPECT_NE(message("laser: {rays: 1}\n").find("laser.rays"), std::string::npos);
  EXPECT_NE(message("encoders: {units: furlongs}\n").find("furlongs"), std::string::npos);
  EXPECT_NE(message("motion: {type: scripted}\n").find("script"), std::string::npos);
  // A world that does not exist fails when the bag is made, naming the file.
  const sim::Scenario scenario =
      sim::loadScenarioYaml(writeScenario(directory, "world: atlantis\n"), kWorlds);
  try {
    simulateToBag(scenario, directory + "/x.bag", "");
    FAIL() << "missing world accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("atlantis"), std::string::npos);
  }
  EXPECT_FALSE(std::ifstream(directory + "/x.bag").good());
  EXPECT_FALSE(std::ifstream(directory + "/x.bag.partial").good());
}

TEST(SimBag, DefaultFileNames)
{
  sim::Scenario scenario;
  scenario.name = "office";
  EXPECT_EQ(defaultSimulationBagPath(scenario), "office.bag");
  EXPECT_EQ(defaultTruthPath("office.bag"), "office_truth.yaml");
  EXPECT_EQ(defaultTruthPath("/tmp/run.2.bag"), "/tmp/run.2_truth.yaml");
  EXPECT_EQ(defaultTruthPath("run"), "run_truth.yaml");
  EXPECT_EQ(defaultTruthPath(".bag"), ".bag_truth.yaml");
}

TEST(SimBag, SimulateToFilesWritesTheRunAndRefusesALogItCannotGive)
{
  const Scratch scratch;
  const std::string& directory = scratch;
  const sim::Scenario scenario =
      sim::loadScenarioYaml(writeScenario(directory, kScenario), kWorlds);
  SimulationFiles files;
  files.bag_path = directory + "/run.bag";
  std::ostringstream out, err;
  ASSERT_EQ(simulateToFiles(scenario, files, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("simulated 3 s of 'small' (diff_drive)"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("truth: " + directory + "/run_truth.yaml"), std::string::npos);
  EXPECT_TRUE(std::ifstream(directory + "/run.bag").good());
  EXPECT_TRUE(std::ifstream(directory + "/run_truth.yaml").good());

  // A tricycle log needs a tricycle robot with the tracker: refused (usage, 2), nothing written.
  files.bag_path = directory + "/refused.bag";
  files.tricycle_log_path = directory + "/refused.log";
  std::ostringstream refused_out, refused_err;
  EXPECT_EQ(simulateToFiles(scenario, files, refused_out, refused_err), 2);
  EXPECT_NE(refused_err.str().find("--tricycle-log needs a tricycle robot"), std::string::npos);
  EXPECT_FALSE(std::ifstream(directory + "/refused.bag").good());
  EXPECT_FALSE(std::ifstream(directory + "/refused.log").good());
}
}  // namespace
}  // namespace odometry_calibration
