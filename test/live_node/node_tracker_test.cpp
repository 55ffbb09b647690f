// rostest (test/node_tracker.test): the node with `ego_motion.source: pose` on a simulated
// tricycle whose sensor pose comes from an external tracker; ~calibrate fits the tricycle model
// (seed 003) and recovers the truth, and ~odom then tracks base_link.
#include <filesystem>
#include <map>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/CalibrationPair.h"

namespace odometry_calibration {
namespace {

using test::waitFor;
const std::string kNode = "/odometry_calibration";

TEST(NodeTracker, FitsTheTricycleFromTrackerPoses)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const YAML::Node truth = YAML::LoadFile(bag.substr(0, bag.size() - 4) + "_truth.yaml");
  std::size_t pairs = 0;
  std::string pair_frame, odom_child;
  auto on_pair = [&](const odometry_calibration::CalibrationPair::ConstPtr& m) {
    ++pairs;
    pair_frame = m->header.frame_id;
  };
  auto on_odom = [&](const nav_msgs::Odometry::ConstPtr& m) { odom_child = m->child_frame_id; };
  ros::Subscriber s1 =
      handle.subscribe<odometry_calibration::CalibrationPair>(kNode + "/pairs", 1000, on_pair);
  ros::Subscriber s2 = handle.subscribe<nav_msgs::Odometry>(kNode + "/odom", 100, on_odom);
  ASSERT_TRUE(waitFor([&] { return test::nodeRunning("/player"); }, 30));
  ASSERT_TRUE(waitFor([&] { return !test::nodeRunning("/player"); }, 200));
  waitFor([] { return false; }, 1.0);
  ASSERT_GT(pairs, 100u);

  odometry_calibration::Calibrate fit;
  fit.request.model = "tricycle";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  // keyframes.fit_intervals_s: the fit interval was chosen among three candidates and is kept
  // with the fit (a model predicts windows of the length it was fitted on).
  const std::string& message = fit.response.message;
  const std::size_t chosen_at = message.find("fit interval T = ");
  ASSERT_NE(chosen_at, std::string::npos) << message;
  const double chosen = std::stod(message.substr(chosen_at + 17));
  EXPECT_TRUE(chosen == 0.3 || chosen == 0.5 || chosen == 1.0) << message;
  EXPECT_NE(message.find(" m (chosen)"), std::string::npos) << message;
  const YAML::Node last_fit = YAML::LoadFile(output_directory + "/last_fit.yaml");
  EXPECT_NEAR(last_fit["fit_interval_s"].as<double>(), chosen, 1e-6);
  std::map<std::string, double> p;
  for (const auto& parameter : fit.response.report.parameters)
    p[parameter.name] = parameter.value;
  const YAML::Node robot = truth["robot"];
  EXPECT_NEAR(p["steering_scale"], robot["steering_scale"].as<double>(), 0.01);
  EXPECT_NEAR(p["traction_scale"], robot["traction_scale_m_per_turn"].as<double>(), 1e-4);
  EXPECT_NEAR(p["axis_length"], robot["axis_length_m"].as<double>(), 0.03);
  EXPECT_NEAR(p["steering_offset"], robot["steering_offset_rad"].as<double>(), 0.005);
  const YAML::Node laser = truth["T_base_laser"];
  ASSERT_TRUE(fit.response.report.has_extrinsic);
  EXPECT_NEAR(fit.response.report.T_base_laser.x, laser["x"].as<double>(), 0.03);
  EXPECT_NEAR(fit.response.report.T_base_laser.y, laser["y"].as<double>(), 0.02);
  EXPECT_NEAR(fit.response.report.T_base_laser.theta, laser["theta"].as<double>(), 0.01);
  EXPECT_EQ(odom_child, "base_link");
  std::filesystem::remove_all(output_directory);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_tracker_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
