// rostest (test/live_node/node_gyro.test): the live node with the gyro (gyro.topic) on a simulated
// drive (config/sim/scenarios/diff_drive_gyro.yaml: the gyro 1.5 % high, 0.01 rad/s bias, its
// clock 20 ms late): it subscribes to the IMU, fits the gyro's scale, bias and time offset on
// ~calibrate against the laser's pairs, saves them in result.yaml; calibrate_bag on the same
// bag and configuration gives the same values, and both are within the acceptance (0.1 %,
// 1e-4 rad/s, 2 ms). After the fit the node watches the gyro: "gyro health" OK on /diagnostics,
// and ~odom takes its heading from it (the configuration's gyro.odom_heading).
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"

namespace odometry_calibration {
namespace {

/// The node's last "…: gyro health" status on /diagnostics (its level and message).
class GyroHealthDiagnostic
{
public:
  GyroHealthDiagnostic()
      : subscriber_(
            ros::NodeHandle().subscribe("/diagnostics", 100, &GyroHealthDiagnostic::on, this))
  {
  }
  bool seen() const { return seen_; }
  int level() const { return level_; }
  const std::string& message() const { return message_; }

private:
  void on(const diagnostic_msgs::DiagnosticArray& array)
  {
    const std::string suffix = ": gyro health";
    for (const diagnostic_msgs::DiagnosticStatus& status : array.status) {
      if (status.name.size() >= suffix.size() &&
          status.name.compare(status.name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        seen_ = true;
        level_ = status.level;
        message_ = status.message;
      }
    }
  }
  ros::Subscriber subscriber_;
  bool seen_ = false;
  int level_ = -1;
  std::string message_;
};

TEST(NodeGyro, NodeAndCalibrateBagGiveTheSameGyroScaleBiasAndClock)
{
  ros::NodeHandle private_handle("~");
  std::string bag, config, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("config", config));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const std::string node_output = output_directory + "/node";
  ASSERT_TRUE(ros::service::waitForService("/gyro/calibrate", ros::Duration(60)));

  // Played at twice the recorded speed; then until the pairs file stops growing for 5 s.
  const std::string play = "rosbag play --clock --quiet -d 2 -r 2 " + bag +
                           " --wait-for-subscribers --topics /joint_states /scan /imu/data > " +
                           output_directory + "/play.log 2>&1";
  ASSERT_EQ(std::system(play.c_str()), 0) << play;
  test::waitUntilSettled<std::size_t>([&] { return test::fileLines(node_output + "/pairs.csv"); },
                                      5, 60);

  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call("/gyro/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  EXPECT_NE(fit.response.message.find("gyro: scale"), std::string::npos) << fit.response.message;
  // gyro.odom_heading: true in the configuration: ~odom turns with the gyro from now on.
  EXPECT_NE(fit.response.message.find("~odom's heading from the gyro (gyro.odom_heading)"),
            std::string::npos)
      << fit.response.message;
  // The fitted gyro is watched from now on (the diagnostics run on the wall clock).
  GyroHealthDiagnostic health;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!health.seen() && std::chrono::steady_clock::now() < give_up) {
    ros::WallDuration(0.1).sleep();
    ros::spinOnce();
  }
  ASSERT_TRUE(health.seen()) << "no gyro health status on /diagnostics after the fit";
  EXPECT_EQ(health.level(), diagnostic_msgs::DiagnosticStatus::OK) << health.message();
  EXPECT_EQ(health.message(), "ok");
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call("/gyro/save", save));
  ASSERT_TRUE(save.response.success) << save.response.message;

  const std::string bag_output = output_directory + "/calibrate_bag";
  ASSERT_TRUE(test::runCalibrateBag(config, bag, bag_output))
      << test::readText(bag_output + ".log");
  const YAML::Node node_gyro = YAML::LoadFile(node_output + "/result.yaml")["gyro"];
  const YAML::Node bag_gyro = YAML::LoadFile(bag_output + "/result.yaml")["gyro"];
  ASSERT_TRUE(node_gyro && node_gyro["fitted"].as<bool>());
  ASSERT_TRUE(bag_gyro && bag_gyro["fitted"].as<bool>());
  // The same pairs, the same readings: the same fit (to well below its sigmas).
  EXPECT_EQ(node_gyro["pairs"].as<int>(), bag_gyro["pairs"].as<int>());
  EXPECT_NEAR(node_gyro["scale"].as<double>(), bag_gyro["scale"].as<double>(), 1e-6);
  EXPECT_NEAR(node_gyro["bias_rad_s"].as<double>(), bag_gyro["bias_rad_s"].as<double>(), 1e-7);
  EXPECT_NEAR(node_gyro["time_offset_s"].as<double>(), bag_gyro["time_offset_s"].as<double>(),
              1e-5);
  for (const YAML::Node& gyro : {node_gyro, bag_gyro}) {
    EXPECT_NEAR(gyro["scale"].as<double>(), 1.015, 0.001 * 1.015);
    EXPECT_NEAR(gyro["bias_rad_s"].as<double>(), 0.01, 1e-4);
    EXPECT_NEAR(gyro["time_offset_s"].as<double>(), -0.02, 0.002);
    RecordProperty("gyro", YAML::Dump(gyro));
  }
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_gyro_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
