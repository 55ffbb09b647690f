// rostest (test/node_replay_mecanum.test): a simulated mecanum bag (mecanum_office: one wheel
// 3 % larger) played through the live node with config/mecanum.yaml. ~calibrate with the GP
// and then with the mecanum model both succeed mid-run; the mecanum fit recovers the four radii
// (1 %), lx + ly (2 %) and the laser pose (1 cm / 1 deg); ~odom then follows the ground truth
// within the diff-drive replay test's tolerance (0.5 % of the distance, a tenth of the nominal
// odometry's error).
#include <cmath>
#include <filesystem>
#include <map>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/CalibrationPair.h"
#include "odometry_calibration/ros/conversions.h"
#include "trajectory_comparison.h"

namespace odometry_calibration {
namespace {

using test::waitFor;

const std::string kNode = "/odometry_calibration";

using test::Stamped;

TEST(NodeReplayMecanum, GpAndMecanumFitsSucceedAndOdometryFollowsTheTruth)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const YAML::Node truth = YAML::LoadFile(bag.substr(0, bag.size() - 4) + "_truth.yaml");

  std::vector<Stamped> odometry, ground_truth;
  std::size_t pairs_seen = 0;
  auto on_odom = [&](const nav_msgs::Odometry::ConstPtr& m) {
    odometry.push_back({m->header.stamp.toSec(), ros_conversions::fromPoseMsg(m->pose.pose)});
  };
  auto on_truth = [&](const nav_msgs::Odometry::ConstPtr& m) {
    ground_truth.push_back({m->header.stamp.toSec(), ros_conversions::fromPoseMsg(m->pose.pose)});
  };
  nav_msgs::Path nominal_path;
  auto on_nominal = [&](const nav_msgs::Path::ConstPtr& m) { nominal_path = *m; };
  auto on_pair = [&](const odometry_calibration::CalibrationPair::ConstPtr&) { ++pairs_seen; };
  ros::Subscriber s1 = handle.subscribe<nav_msgs::Odometry>(kNode + "/odom", 10000, on_odom);
  ros::Subscriber s2 = handle.subscribe<nav_msgs::Odometry>("/ground_truth/odom", 10000, on_truth);
  ros::Subscriber s3 = handle.subscribe<nav_msgs::Path>(kNode + "/path/nominal", 1, on_nominal);
  ros::Subscriber s4 =
      handle.subscribe<odometry_calibration::CalibrationPair>(kNode + "/pairs", 1000, on_pair);

  ASSERT_TRUE(ros::service::waitForService(kNode + "/calibrate", ros::Duration(60)));
  ASSERT_TRUE(waitFor([&] { return pairs_seen >= 80; }, 120)) << pairs_seen << " pairs";
  odometry_calibration::Calibrate gp;
  gp.request.model = "gp";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", gp));
  EXPECT_TRUE(gp.response.success) << gp.response.message;
  odometry_calibration::Calibrate fit;
  fit.request.model = "mecanum";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  ros::spinOnce();
  const double fit_stamp_s = odometry.empty() ? 0.0 : odometry.back().stamp_s + 0.5;

  std::map<std::string, double> p;
  for (const auto& parameter : fit.response.report.parameters)
    p[parameter.name] = parameter.value;
  const YAML::Node robot = truth["robot"];
  const double radius = robot["wheel_radius_m"].as<double>();
  const double radius_fl = robot["wheel_radius_fl_m"].as<double>();
  EXPECT_NEAR(p["wheel_radius_front_left"], radius_fl, 0.01 * radius_fl);
  EXPECT_NEAR(p["wheel_radius_front_right"], radius, 0.01 * radius);
  EXPECT_NEAR(p["wheel_radius_rear_left"], radius, 0.01 * radius);
  EXPECT_NEAR(p["wheel_radius_rear_right"], radius, 0.01 * radius);
  const double lever = robot["half_length_m"].as<double>() + robot["half_width_m"].as<double>();
  EXPECT_NEAR(p["lx_plus_ly"], lever, 0.02 * lever);
  const YAML::Node laser = truth["T_base_laser"];
  EXPECT_NEAR(p["sensor_x"], laser["x"].as<double>(), 0.01);
  EXPECT_NEAR(p["sensor_y"], laser["y"].as<double>(), 0.01);
  EXPECT_NEAR(p["sensor_theta"], laser["theta"].as<double>(), M_PI / 180);

  // The player ends: every message has been sent.
  ASSERT_TRUE(waitFor([&] { return test::nodeRunning("/player"); }, 10));
  ASSERT_TRUE(waitFor([&] { return !test::nodeRunning("/player"); }, 180));
  waitFor([] { return false; }, 2.0);  // the last messages and the 1 Hz paths

  // ~odom (integrated again from the start with the fitted model) against the ground truth,
  // compared with the nominal odometry.
  ASSERT_NO_FATAL_FAILURE(test::expectCorrectedOdometryEndsNearTheTruth(
      odometry, fit_stamp_s, ground_truth, nominal_path));
  std::filesystem::remove_all(output_directory);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_replay_mecanum_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
