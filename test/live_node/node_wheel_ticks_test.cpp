// rostest (test/node_wheel_ticks.test, test/node_joint_velocity.test): the live node takes a
// wheel input other than JointState positions as calibrate_bag does. Per-wheel tick topics: the
// node stamps each tick with its receive time (the /clock of the replay), calibrate_bag with its
// record time; both unwrap the 8-bit counters, align the wheels at the left wheel's instants and
// fit: the wheel parameters agree within 0.1 % (the receive times jitter with the machine's load;
// 0.013 % measured on a busy 2-core machine). Velocity-only JointState: stamped messages,
// integrated alike, so the same pairs byte for byte and the parameters within 0.01 %.
// Parameters of the test (defaults: the tick test's): `node`, `config` (in `configs`), `topics`
// played, `rate` of the replay, `tolerance` (relative), `same_pairs`.
#include <cmath>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"

namespace odometry_calibration {
namespace {

TEST(NodeWheelTicks, NodeAndCalibrateBagGiveTheSameWheels)
{
  ros::NodeHandle private_handle("~");
  std::string bag, configs, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("configs", configs));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const std::string node = private_handle.param<std::string>("node", "ticks");
  const std::string config = private_handle.param<std::string>("config", "wheel_ticks.yaml");
  const std::string topics =
      private_handle.param<std::string>("topics", "/left_wheel_ticks /right_wheel_ticks /scan");
  const double rate = private_handle.param("rate", 1.0);
  const double tolerance = private_handle.param("tolerance", 1e-3);
  const bool same_pairs = private_handle.param("same_pairs", false);
  ASSERT_TRUE(ros::service::waitForService("/" + node + "/calibrate", ros::Duration(60)));
  const std::string play = "rosbag play --clock --hz 1000 --quiet -d 2 -r " + std::to_string(rate) +
                           " " + bag + " --wait-for-subscribers --topics " + topics + " > " +
                           output_directory + "/play.log 2>&1";
  ASSERT_EQ(std::system(play.c_str()), 0) << play;
  const std::string pairs = output_directory + "/" + node + "/pairs.csv";
  test::waitUntilSettled<std::size_t>([&] { return test::fileLines(pairs); }, 5, 60);

  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call("/" + node + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  const std::string bag_output = output_directory + "/calibrate_bag";
  ASSERT_TRUE(test::runCalibrateBag(configs + "/" + config, bag, bag_output))
      << test::readText(bag_output + ".log");
  const YAML::Node node_fit = YAML::LoadFile(output_directory + "/" + node + "/last_fit.yaml");
  const YAML::Node bag_fit = YAML::LoadFile(bag_output + "/result.yaml");
  EXPECT_GT(node_fit["fit"]["pairs"].as<int>(), 60);
  if (same_pairs) {
    const std::string node_text = test::readText(pairs);
    EXPECT_GT(node_text.size(), 1000u);
    EXPECT_EQ(node_text, test::readText(bag_output + "/pairs.csv"));
  }
  for (const char* parameter : {"left_wheel_radius", "right_wheel_radius", "wheel_separation"}) {
    const double bag_value = bag_fit["parameters"][parameter]["value"].as<double>();
    const double node_value = node_fit["parameters"][parameter]["value"].as<double>();
    EXPECT_NEAR(node_value, bag_value, tolerance * bag_value) << parameter;
    RecordProperty(parameter,
                   std::to_string(100.0 * std::abs(node_value / bag_value - 1.0)) + " %");
  }
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_wheel_ticks_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
