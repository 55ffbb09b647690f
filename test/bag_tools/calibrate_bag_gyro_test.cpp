// End-to-end: the gyro as a further source (gyro.topic) through calibrate_bag. One simulated
// drive (config/sim/scenarios/diff_drive_gyro.yaml: the gyro 1.5 % high, 0.01 rad/s bias, its
// clock 20 ms late) written as a ROS 1 bag, a rosbag2 .db3 and an MCAP file: each gives the
// gyro's scale, bias and time offset within the acceptance (0.1 %, 1e-4 rad/s, 2 ms) and the same
// values; the wheels and the laser's pose are those of the run without the gyro.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kTool = CALIBRATE_BAG_PROGRAM;

class CalibrateBagGyro : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/calibrate_bag_gyro_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_gyro.yaml",
                                                   kConfig + "/sim/worlds");
    scenario.duration_s = 180.0;
    simulateToBag(scenario, directory_ + "/drive.bag", "");
    simulateToBag(scenario, directory_ + "/drive_db3", "", nullptr, BagFormat::kDb3);
    simulateToBag(scenario, directory_ + "/drive_mcap", "", nullptr, BagFormat::kMcapZstd);
    // The same configuration without the gyro (nor ~odom's heading from it).
    const std::string text =
        std::regex_replace(test_support::readFile(kConfig + "/diff_drive_gyro.yaml"),
                           std::regex("odom_heading: true"), "odom_heading: false");
    std::ofstream(directory_ + "/no_gyro.yaml")
        << std::regex_replace(text, std::regex("topic: /imu/data"), "topic: \"\"");
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  /// calibrate_bag on `bag` with `config` into directory_/<name>; its result.yaml.
  static YAML::Node run(const std::string& config, const std::string& bag, const std::string& name)
  {
    const std::string output = directory_ + "/" + name;
    const std::string command = kTool + " --config " + config + " " + bag +
                                " --quiet --output-dir " + output + " > " + output + ".txt 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << test_support::readFile(output + ".txt");
    return YAML::LoadFile(output + "/result.yaml");
  }

  static std::string directory_;
};

std::string CalibrateBagGyro::directory_;

TEST_F(CalibrateBagGyro, ScaleBiasAndClockFromEveryFormatTheWheelsUnmoved)
{
  const std::string config = kConfig + "/diff_drive_gyro.yaml";
  const YAML::Node bag = run(config, directory_ + "/drive.bag", "bag");
  const YAML::Node gyro = bag["gyro"];
  ASSERT_TRUE(gyro && gyro["fitted"].as<bool>()) << YAML::Dump(bag);
  EXPECT_EQ(gyro["topic"].as<std::string>(), "/imu/data");
  EXPECT_NEAR(gyro["scale"].as<double>(), 1.015, 0.001 * 1.015);
  EXPECT_NEAR(gyro["bias_rad_s"].as<double>(), 0.01, 1e-4);
  // Its clock 20 ms late: the encoders' values at the gyro's stamp - 20 ms.
  EXPECT_NEAR(gyro["time_offset_s"].as<double>(), -0.02, 0.002);
  EXPECT_LT(gyro["scale_sigma"].as<double>(), 0.001);
  EXPECT_LT(gyro["bias_rad_s_sigma"].as<double>(), 1e-4);
  for (const char* other : {"drive_db3", "drive_mcap"}) {
    const YAML::Node same = run(config, directory_ + "/" + other, other)["gyro"];
    for (const char* key : {"scale", "bias_rad_s", "time_offset_s"})
      EXPECT_EQ(same[key].as<double>(), gyro[key].as<double>()) << other << ": " << key;
  }
  // The gyro adds nothing to the wheels' fit: the same values and σ without it (the acceptance:
  // σ(separation) at most 1.01 times, the wheels moved by less than their σ).
  const YAML::Node without = run(directory_ + "/no_gyro.yaml", directory_ + "/drive.bag", "none");
  EXPECT_FALSE(without["gyro"]);
  EXPECT_EQ(YAML::Dump(without["model"]), YAML::Dump(bag["model"]));
  EXPECT_EQ(YAML::Dump(without["parameters"]), YAML::Dump(bag["parameters"]));  // values and σ
}

}  // namespace
}  // namespace odometry_calibration
