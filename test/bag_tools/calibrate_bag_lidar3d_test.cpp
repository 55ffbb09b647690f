// Issue 19's acceptance: calibrate_bag on simulated office runs of a differential-drive robot
// with a 16-beam 3D lidar (PointCloud2), mounted level and pitched 2 deg, recovers the wheel
// radii and separation within 0.5 % and the lidar's x, y, yaw within 1 cm / 0.01 rad; and
// PointCloud2 messages it cannot use are skipped, counted and named, never a crash.
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kTool = CALIBRATE_BAG_PROGRAM;
constexpr double kPitch = 2.0 * M_PI / 180.0;

class CalibrateBagLidar3d : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/calibrate_bag_lidar3d_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    scenario_ = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office_lidar3d.yaml",
                                      kConfig + "/sim/worlds");
    scenario_.duration_s = 40.0;  // 400 clouds of ~14000 points: 128 MB
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// Simulates the scenario, runs calibrate_bag (with `config_text` as its config) and returns
  /// its result.yaml; the exit status must be 0.
  YAML::Node calibrate(const std::string& config_text)
  {
    const std::string bag = directory_ + "/run.bag";
    simulateToBag(scenario_, bag, "");
    const std::string config = directory_ + "/config.yaml";
    std::ofstream(config) << config_text;
    const std::string command = kTool + " --config " + config + " " + bag +
                                " --quiet --output-dir " + directory_ + "/out > " + directory_ +
                                "/stdout.txt 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << test_support::readFile(directory_ + "/stdout.txt");
    fs::remove(bag);
    return YAML::LoadFile(directory_ + "/out/result.yaml");
  }

  /// The scenario's truth: r_L 0.0765, r_R 0.0775, b 0.32, lidar (0.145, 0.01, 0.02).
  void expectTruth(const YAML::Node& result)
  {
    const YAML::Node p = result["parameters"];
    EXPECT_NEAR(p["left_wheel_radius"]["value"].as<double>(), 0.0765, 0.0765 * 0.005);
    EXPECT_NEAR(p["right_wheel_radius"]["value"].as<double>(), 0.0775, 0.0775 * 0.005);
    EXPECT_NEAR(p["wheel_separation"]["value"].as<double>(), 0.32, 0.32 * 0.005);
    EXPECT_NEAR(p["sensor_x"]["value"].as<double>(), 0.145, 0.01);
    EXPECT_NEAR(p["sensor_y"]["value"].as<double>(), 0.01, 0.01);
    EXPECT_NEAR(p["sensor_theta"]["value"].as<double>(), 0.02, 0.01);
    EXPECT_TRUE(result["fit"]["converged"].as<bool>());
  }

  std::string directory_;
  sim::Scenario scenario_;
};

TEST_F(CalibrateBagLidar3d, LevelLidarRecoversTheTruth)
{
  expectTruth(calibrate(test_support::readFile(kConfig + "/diff_drive_lidar3d.yaml")));
}

TEST_F(CalibrateBagLidar3d, LidarPitchedTwoDegreesIsLevelledAndRecoversTheTruth)
{
  scenario_.laser.pitch_rad = kPitch;
  std::string config = test_support::readFile(kConfig + "/diff_drive_lidar3d.yaml");
  const std::string level = "    pitch_rad: 0.0 ";
  const auto at = config.find(level);
  ASSERT_NE(at, std::string::npos);
  config.replace(at, level.size(), "    pitch_rad: " + std::to_string(kPitch) + " ");
  expectTruth(calibrate(config));
}

TEST_F(CalibrateBagLidar3d, ScanFromPointsPitchedTwoDegreesRecoversTheTruth)
{
  // The in-band voxels matched unbinned, each at its own bearing, on the levelled 2 deg run.
  scenario_.laser.pitch_rad = kPitch;
  std::string config = test_support::readFile(kConfig + "/diff_drive_lidar3d.yaml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"    scan_from: bins ", "    scan_from: points "},
        {"    pitch_rad: 0.0 ", "    pitch_rad: " + std::to_string(kPitch) + " "}}) {
    const auto at = config.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    config.replace(at, from.size(), to);
  }
  expectTruth(calibrate(config));
}

TEST_F(CalibrateBagLidar3d, AbsolutePointStampsCalibrateAsWellAsRelativeOnes)
{
  // The same run written with Velodyne's relative `time` (FLOAT32 s after the stamp) and with
  // Hesai's absolute `timestamp` (FLOAT64 s since the epoch): the times are the same to float
  // rounding, so the fits must agree far more closely than the tolerances, which a bag whose
  // absolute times were ignored (no sweep compensation) or misread would not.
  const std::string config = test_support::readFile(kConfig + "/diff_drive_lidar3d.yaml");
  const YAML::Node relative = calibrate(config);
  scenario_.laser.point_times = "absolute";
  const YAML::Node absolute = calibrate(config);
  expectTruth(absolute);
  const std::string output = test_support::readFile(directory_ + "/stdout.txt");
  EXPECT_EQ(output.find("without their per-point times"), std::string::npos) << output;
  for (const char* name : {"left_wheel_radius", "right_wheel_radius", "wheel_separation",
                           "sensor_x", "sensor_y", "sensor_theta"}) {
    EXPECT_NEAR(absolute["parameters"][name]["value"].as<double>(),
                relative["parameters"][name]["value"].as<double>(), 2e-5)
        << name;
  }
}

TEST_F(CalibrateBagLidar3d, CloudsWithImpossibleAbsoluteStampsAreUsedWithoutTimesAndCounted)
{
  scenario_.duration_s = 8.0;
  scenario_.laser.point_times = "absolute";
  const std::string bag = directory_ + "/run.bag";
  simulateToBag(scenario_, bag, "");
  // A copy of a cloud restamped 3 s later (its points' absolute times are then 3 s before the
  // stamp), in a second bag: its times must not be used.
  const std::string odd_bag = directory_ + "/odd.bag";
  {
    sensor_msgs::PointCloud2 cloud;
    {
      rosbag::Bag in(bag, rosbag::bagmode::Read);
      rosbag::View view(in, rosbag::TopicQuery(scenario_.laser.topic));
      cloud = *view.begin()->instantiate<sensor_msgs::PointCloud2>();
    }
    cloud.header.stamp += ros::Duration(3.0);
    rosbag::Bag out(odd_bag, rosbag::bagmode::Write);
    out.write(scenario_.laser.topic, cloud.header.stamp, cloud);
  }
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive_lidar3d.yaml");
  const BagRunResult run = runBags({bag, odd_bag}, config);
  EXPECT_EQ(run.counts.bad_ego_messages, 0u);
  EXPECT_EQ(run.counts.clouds_without_times, 1u);
  EXPECT_NE(
      run.counts.first_cloud_time_problem.find("per-point times of field 'timestamp' ignored"),
      std::string::npos)
      << run.counts.first_cloud_time_problem;
  EXPECT_NE(run.counts.first_cloud_time_problem.find("s from the stamp, beyond the 0.5 s"),
            std::string::npos)
      << run.counts.first_cloud_time_problem;
  const std::string notes =
      formatBagRunSummary(run, run.counts, run.session->source(0).collectionNotes());
  EXPECT_NE(notes.find("1 PointCloud2 messages used without their per-point times"),
            std::string::npos)
      << notes;
  // The run's own clouds alone: every time used.
  const BagRunResult clean = runBags({bag}, config);
  EXPECT_EQ(clean.counts.clouds_without_times, 0u);
  EXPECT_GT(clean.pairs.size(), 10u);
}

/// A PointCloud2 of `points` x, y, z float triples in `frame`, stamped `stamp`.
sensor_msgs::PointCloud2 cloudMessage(const std::vector<float>& xyz, const std::string& frame,
                                      const ros::Time& stamp, bool with_z = true)
{
  sensor_msgs::PointCloud2 message;
  message.header.stamp = stamp;
  message.header.frame_id = frame;
  const int fields = with_z ? 3 : 2;
  for (int f = 0; f < fields; ++f) {
    sensor_msgs::PointField field;
    field.name = std::string(1, "xyz"[f]);
    field.offset = 4 * f;
    field.datatype = sensor_msgs::PointField::FLOAT32;
    field.count = 1;
    message.fields.push_back(field);
  }
  message.point_step = 12;
  message.height = 1;
  message.width = static_cast<std::uint32_t>(xyz.size() / 3);
  message.row_step = message.point_step * message.width;
  message.data.resize(message.row_step);
  if (!message.data.empty())
    std::memcpy(message.data.data(), xyz.data(), message.data.size());
  return message;
}

TEST_F(CalibrateBagLidar3d, UnusableCloudsAreSkippedCountedAndNamed)
{
  scenario_.duration_s = 8.0;
  const std::string bag = directory_ + "/run.bag";
  simulateToBag(scenario_, bag, "");
  // A second bag with one bad cloud of each kind, inside the first one's time span.
  const std::string bad_bag = directory_ + "/bad.bag";
  {
    rosbag::Bag out(bad_bag, rosbag::bagmode::Write);
    const ros::Time start(scenario_.start_time_s + 3.05);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> wall;  // a few points on a wall 2 m ahead: too sparse for 20 bearings
    for (int i = 0; i < 5; ++i)
      wall.insert(wall.end(), {2.0f, 0.1f * static_cast<float>(i), 0.0f});
    const std::vector<sensor_msgs::PointCloud2> bad = {
        cloudMessage({}, "lidar", start),                               // empty
        cloudMessage({1.0f, 2.0f, 1.0f, 2.0f}, "lidar", start, false),  // no z
        cloudMessage({nan, nan, nan, nan, 1.0f, nan}, "lidar", start),  // NaN points only
        cloudMessage(wall, "lidar", start),                             // sparse in the band
        cloudMessage(wall, "another_lidar", start),                     // unknown frame
        cloudMessage(wall, "", start),                                  // no frame
    };
    for (std::size_t i = 0; i < bad.size(); ++i) {
      auto message = bad[i];
      message.header.stamp = start + ros::Duration(0.5 * static_cast<double>(i));
      out.write(scenario_.laser.topic, message.header.stamp, message);
    }
  }
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive_lidar3d.yaml");
  const BagRunResult run = runBags({bag, bad_bag}, config);
  EXPECT_EQ(run.counts.bad_ego_messages, 6u);
  EXPECT_EQ(run.counts.ego_messages, 80u + 6u);  // 80 sweeps end within 8 s
  EXPECT_GT(run.pairs.size(), 10u);              // the good clouds still pair
  EXPECT_EQ(run.counts.first_bad_ego_message, "the cloud is empty");
  const std::string notes =
      formatBagRunSummary(run, run.counts, run.session->source(0).collectionNotes());
  EXPECT_NE(notes.find("skipped 6 PointCloud2 messages"), std::string::npos) << notes;

  // Each reason on its own: the sparse cloud names the band and what remained.
  CalibrationConfig sparse_config = config;
  const std::string sparse_bag = directory_ + "/sparse.bag";
  {
    rosbag::Bag out(sparse_bag, rosbag::bagmode::Write);
    std::vector<float> wall;
    for (int i = 0; i < 5; ++i)
      wall.insert(wall.end(), {2.0f, 0.1f * static_cast<float>(i), 0.0f});
    const ros::Time stamp(scenario_.start_time_s + 3.05);
    out.write(scenario_.laser.topic, stamp, cloudMessage(wall, "lidar", stamp));
    const ros::Time later(scenario_.start_time_s + 3.55);
    out.write(scenario_.laser.topic, later, cloudMessage(wall, "other", later));
  }
  const BagRunResult sparse = runBags({bag, sparse_bag}, sparse_config);
  EXPECT_EQ(sparse.counts.bad_ego_messages, 2u);
  EXPECT_NE(sparse.counts.first_bad_ego_message.find(
                "too few points in the height band [-0.3, 0.3] m about "
                "the sensor's plane: 5 bearings left (20 needed)"),
            std::string::npos)
      << sparse.counts.first_bad_ego_message;
}

}  // namespace
}  // namespace odometry_calibration
