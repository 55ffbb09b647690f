// rostest (test/live_node/node_front_rear.test, issue 35): the live node with two lasers, front and
// rear (ego_motion.sources), on a simulated bag of the front/rear robot: it subscribes to both
// lasers, pairs each against the same encoders, fits the wheels and both poses jointly on
// ~calibrate, publishes base_link -> each laser's frame on tf and saves result.yaml with every
// sensor; calibrate_bag on the same bag and configuration gives the same wheels and poses.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"

namespace odometry_calibration {
namespace {

using test::fileLines;
using test::waitFor;

/// The line counts of the node's pairs files, one per source.
std::vector<std::size_t> pairFileLines(const std::string& node_output)
{
  return {fileLines(node_output + "/source_0/pairs.csv"),
          fileLines(node_output + "/source_1/pairs.csv")};
}

/// The yaw of a planar rotation's quaternion [rad].
double yaw(const geometry_msgs::Quaternion& q)
{
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

double wrap(double angle_rad)
{
  return std::atan2(std::sin(angle_rad), std::cos(angle_rad));
}

/// The names of the node's /diagnostics statuses.
class StatusNames
{
public:
  StatusNames()
      : subscriber_(ros::NodeHandle().subscribe("/diagnostics", 100, &StatusNames::on, this))
  {
  }
  const std::set<std::string>& names() const { return names_; }

private:
  void on(const diagnostic_msgs::DiagnosticArray& array)
  {
    for (const diagnostic_msgs::DiagnosticStatus& status : array.status)
      names_.insert(status.name);
  }
  ros::Subscriber subscriber_;
  std::set<std::string> names_;
};

TEST(NodeFrontRear, NodeAndCalibrateBagGiveTheSameWheelsAndBothLaserPoses)
{
  ros::NodeHandle private_handle("~");
  std::string bag, config, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("config", config));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const std::string node_output = output_directory + "/node";
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  StatusNames statuses;
  ASSERT_TRUE(ros::service::waitForService("/front_rear/calibrate", ros::Duration(60)));

  // Both lasers' topics played at twice the recorded speed; then until no pairs file grows
  // for 5 s.
  const std::string play = "rosbag play --clock --quiet -d 2 -r 2 " + bag +
                           " --wait-for-subscribers --topics /joint_states /scan_front "
                           "/scan_rear > " +
                           output_directory + "/play.log 2>&1";
  ASSERT_EQ(std::system(play.c_str()), 0) << play;
  test::waitUntilSettled<std::vector<std::size_t>>([&] { return pairFileLines(node_output); }, 5,
                                                   60);
  // Each laser's own statuses on /diagnostics, named by its topic.
  EXPECT_EQ(statuses.names().count("/front_rear: calibration (/scan_front)"), 1u);
  EXPECT_EQ(statuses.names().count("/front_rear: calibration (/scan_rear)"), 1u);

  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call("/front_rear/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  EXPECT_NE(fit.response.message.find("[/scan_rear] pose"), std::string::npos)
      << fit.response.message;
  // Each source's pairs in its own file (three header lines each), all of them counted.
  const std::vector<std::size_t> pair_lines = pairFileLines(node_output);
  EXPECT_EQ(fit.response.report.pairs_collected + 6, pair_lines[0] + pair_lines[1]);
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call("/front_rear/save", save));
  ASSERT_TRUE(save.response.success) << save.response.message;

  const std::string bag_output = output_directory + "/calibrate_bag";
  ASSERT_TRUE(test::runCalibrateBag(config, bag, bag_output))
      << test::readText(bag_output + ".log");

  const YAML::Node node_result = YAML::LoadFile(node_output + "/result.yaml");
  const YAML::Node bag_result = YAML::LoadFile(bag_output + "/result.yaml");
  // The same wheels (and the first sensor's pose, result.yaml's parameters) within 0.01 % ...
  for (const auto& entry : bag_result["parameters"]) {
    const std::string parameter = entry.first.as<std::string>();
    const double bag_value = entry.second["value"].as<double>();
    const double node_value = node_result["parameters"][parameter]["value"].as<double>();
    EXPECT_NEAR(node_value, bag_value, 1e-4 * std::max(std::abs(bag_value), 1e-3)) << parameter;
    RecordProperty(parameter, std::to_string(node_value) + " vs " + std::to_string(bag_value));
  }
  // ... from the same pairs, at the same time offsets, and every sensor's pose alike within
  // 0.1 mm and 1e-4 rad.
  ASSERT_EQ(node_result["sensors"].size(), 2u);
  ASSERT_EQ(bag_result["sensors"].size(), 2u);
  const char* frames[2] = {"laser_front", "laser_rear"};
  // The simulated truth (config/sim/scenarios/diff_drive_front_rear.yaml).
  const double truth[2][3] = {{0.30, 0.0, 0.0}, {-0.30, 0.02, M_PI + 0.03}};
  for (std::size_t s = 0; s < 2; ++s) {
    const YAML::Node node_sensor = node_result["sensors"][s], bag_sensor = bag_result["sensors"][s];
    EXPECT_EQ(node_sensor["frame"].as<std::string>(), frames[s]);
    EXPECT_EQ(node_sensor["topic"].as<std::string>(), bag_sensor["topic"].as<std::string>());
    EXPECT_EQ(node_sensor["pairs"].as<int>(), bag_sensor["pairs"].as<int>()) << s;
    EXPECT_NEAR(node_sensor["time_offset_s"].as<double>(), bag_sensor["time_offset_s"].as<double>(),
                1e-6)
        << s;
    const YAML::Node node_pose = node_sensor["T_base_sensor"],
                     bag_pose = bag_sensor["T_base_sensor"];
    EXPECT_NEAR(node_pose["x_m"].as<double>(), bag_pose["x_m"].as<double>(), 1e-4) << s;
    EXPECT_NEAR(node_pose["y_m"].as<double>(), bag_pose["y_m"].as<double>(), 1e-4) << s;
    EXPECT_NEAR(wrap(node_pose["theta_rad"].as<double>() - bag_pose["theta_rad"].as<double>()), 0.0,
                1e-4)
        << s;
    // Both near the truth (the acceptance's 5 mm and 0.3 degrees).
    EXPECT_NEAR(node_pose["x_m"].as<double>(), truth[s][0], 0.005) << s;
    EXPECT_NEAR(node_pose["y_m"].as<double>(), truth[s][1], 0.005) << s;
    EXPECT_NEAR(wrap(node_pose["theta_rad"].as<double>() - truth[s][2]), 0.0, 0.3 * M_PI / 180)
        << s;
    // base_link -> the laser's frame on tf: the saved pose.
    geometry_msgs::TransformStamped transform;
    ASSERT_TRUE(
        waitFor([&] { return tf_buffer.canTransform("base_link", frames[s], ros::Time(0)); }, 10.0))
        << frames[s];
    transform = tf_buffer.lookupTransform("base_link", frames[s], ros::Time(0));
    EXPECT_NEAR(transform.transform.translation.x, node_pose["x_m"].as<double>(), 1e-6) << s;
    EXPECT_NEAR(transform.transform.translation.y, node_pose["y_m"].as<double>(), 1e-6) << s;
    EXPECT_NEAR(wrap(yaw(transform.transform.rotation) - node_pose["theta_rad"].as<double>()), 0.0,
                1e-6)
        << s;
    // Each laser's joint in the saved URDF, its own result under source_<k>/.
    EXPECT_TRUE(std::filesystem::is_regular_file(node_output + "/source_" + std::to_string(s) +
                                                 "/result.yaml"));
  }
  const std::string urdf_text = test::readText(node_output + "/laser_joints.urdf");
  EXPECT_NE(urdf_text.find("<child link=\"laser_rear\"/>"), std::string::npos) << urdf_text;
  // The joint wheels near the truth (radii 0.076 / 0.078 m, separation 0.32 m) within 0.5 %.
  const YAML::Node model = node_result["model"];
  EXPECT_NEAR(model["left_wheel_radius_m"].as<double>(), 0.076, 0.005 * 0.076);
  EXPECT_NEAR(model["right_wheel_radius_m"].as<double>(), 0.078, 0.005 * 0.078);
  EXPECT_NEAR(model["wheel_separation_m"].as<double>(), 0.32, 0.005 * 0.32);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_front_rear_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
