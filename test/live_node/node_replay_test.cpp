// rostest (test/node_replay.test): a simulated bag played through the live node by
// replay.launch. A fit in the middle of the run recovers the true geometry; ~odom then follows
// the ground truth much better than the nominal odometry; tf carries the learned extrinsic; and
// the node's pairs and parameters equal calibrate_bag's on the same bag (issue #10). Also run
// on a 16-beam lidar bag (node_replay_lidar3d.test: PointCloud2, issue 19), with the private
// parameters sensor_frame (the extrinsic's child frame, "laser") and fit_after_pairs (80).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/Marker.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/CalibrationPair.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/ros/conversions.h"
#include "trajectory_comparison.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test::waitFor;

const std::string kNode = "/odometry_calibration";

using test::Stamped;

std::map<std::string, double> parameters(const odometry_calibration::CalibrationReport& report)
{
  std::map<std::string, double> values;
  for (const auto& p : report.parameters)
    values[p.name] = p.value;
  return values;
}

TEST(NodeReplay, FitsMidRunPublishesCorrectedOdometryAndMatchesTheBagTool)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, truth_path, config, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("config", config));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const std::string sensor_frame = private_handle.param<std::string>("sensor_frame", "laser");
  const int fit_after_pairs = private_handle.param("fit_after_pairs", 80);
  truth_path = bag.substr(0, bag.size() - 4) + "_truth.yaml";
  const YAML::Node truth = YAML::LoadFile(truth_path);

  std::vector<Stamped> odometry, ground_truth;
  std::string odom_child, odom_parent;
  double odom_variance_x = 0.0;
  std::size_t pairs_seen = 0;
  auto on_odom = [&](const nav_msgs::Odometry::ConstPtr& m) {
    odometry.push_back({m->header.stamp.toSec(), ros_conversions::fromPoseMsg(m->pose.pose)});
    odom_child = m->child_frame_id;
    odom_parent = m->header.frame_id;
    odom_variance_x = m->pose.covariance[0];
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
  // The live assistant (issue 18): guidance and health on /diagnostics, the rviz marker.
  diagnostic_msgs::DiagnosticStatus guidance_status, health_status;
  auto on_diagnostics = [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    for (const auto& status : m->status) {
      if (status.name == kNode + ": excitation guidance")
        guidance_status = status;
      if (status.name == kNode + ": calibration health")
        health_status = status;
    }
  };
  visualization_msgs::Marker marker;
  auto on_marker = [&](const visualization_msgs::Marker::ConstPtr& m) { marker = *m; };
  ros::Subscriber s5 =
      handle.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100, on_diagnostics);
  ros::Subscriber s6 =
      handle.subscribe<visualization_msgs::Marker>(kNode + "/guidance_marker", 10, on_marker);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);

  ASSERT_TRUE(ros::service::waitForService(kNode + "/calibrate", ros::Duration(60)));
  // Half of the run: fit, then watch the corrected odometry over the other half.
  ASSERT_TRUE(waitFor([&] { return pairs_seen >= static_cast<std::size_t>(fit_after_pairs); }, 120))
      << pairs_seen << " pairs";
  odometry_calibration::Calibrate fit;
  fit.request.model = "diff_drive";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  EXPECT_NE(fit.response.message.find("Guidance: "), std::string::npos) << fit.response.message;
  ros::spinOnce();
  const double fit_stamp_s = odometry.empty() ? 0.0 : odometry.back().stamp_s + 0.5;

  std::map<std::string, double> p = parameters(fit.response.report);
  const YAML::Node robot = truth["robot"];
  EXPECT_NEAR(p["left_wheel_radius"], robot["wheel_radius_left_m"].as<double>(), 0.0005);
  EXPECT_NEAR(p["right_wheel_radius"], robot["wheel_radius_right_m"].as<double>(), 0.0005);
  EXPECT_NEAR(p["wheel_separation"], robot["wheel_separation_m"].as<double>(), 0.003);
  const YAML::Node laser = truth["T_base_laser"];
  EXPECT_NEAR(p["sensor_x"], laser["x"].as<double>(), 0.01);
  EXPECT_NEAR(p["sensor_y"], laser["y"].as<double>(), 0.01);
  EXPECT_NEAR(p["sensor_theta"], laser["theta"].as<double>(), 0.005);

  // The learned extrinsic on tf (static).
  geometry_msgs::TransformStamped transform;
  ASSERT_TRUE(waitFor(
      [&] {
        try {
          transform = tf_buffer.lookupTransform("base_link", sensor_frame, ros::Time(0));
          return std::abs(transform.transform.translation.x - p["sensor_x"]) < 1e-9;
        } catch (const tf2::TransformException&) {
          return false;
        }
      },
      10));
  const Pose2 T_base_laser = ros_conversions::fromTransformMsg(transform.transform);
  EXPECT_NEAR(T_base_laser.y(), p["sensor_y"], 1e-9);
  EXPECT_NEAR(T_base_laser.theta(), p["sensor_theta"], 1e-9);

  // The player ends: every message has been sent.
  ASSERT_TRUE(waitFor([&] { return test::nodeRunning("/player"); }, 10));
  ASSERT_TRUE(waitFor([&] { return !test::nodeRunning("/player"); }, 180));
  waitFor([] { return false; }, 2.0);  // the last messages and the 1 Hz paths

  // ~odom after the fit against the ground truth, compared with the nominal odometry over the
  // same interval.
  EXPECT_EQ(odom_parent, "odom");
  EXPECT_EQ(odom_child, "base_link");
  EXPECT_GT(odom_variance_x, 0.0);
  ASSERT_NO_FATAL_FAILURE(test::expectCorrectedOdometryEndsNearTheTruth(
      odometry, fit_stamp_s, ground_truth, nominal_path));

  // The guidance names every diff_drive parameter with its sigma and target; the health
  // monitor watches the fit and, the robot being unchanged, raises no alarm.
  ASSERT_FALSE(guidance_status.name.empty()) << "no guidance on /diagnostics";
  std::map<std::string, std::string> guidance_values;
  for (const auto& entry : guidance_status.values)
    guidance_values[entry.key] = entry.value;
  EXPECT_EQ(guidance_values["guidance model"], "diff_drive");
  EXPECT_EQ(guidance_values.count("ready to fit"), 1u);
  EXPECT_NE(guidance_values["wheel_separation [m]"].find("sigma"), std::string::npos);
  EXPECT_NE(guidance_status.message.find("pairs"), std::string::npos);
  ASSERT_FALSE(health_status.name.empty()) << "no health monitor on /diagnostics";
  EXPECT_EQ(health_status.level, diagnostic_msgs::DiagnosticStatus::OK) << health_status.message;
  EXPECT_EQ(marker.header.frame_id, "base_link");
  EXPECT_EQ(marker.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_NE(marker.text.find("calibration"), std::string::npos) << marker.text;

  // Same bag, same configuration: calibrate_bag's pairs and parameters.
  const std::string bag_output = output_directory + "/calibrate_bag";
  const std::string command = std::string(ODOMETRY_CALIBRATION_TOOLS_DIR) +
                              "/calibrate_bag --quiet --model diff_drive --config " + config +
                              " --output-dir " + bag_output + " " + bag + " > " + output_directory +
                              "/calibrate_bag.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const PairsFile bag_pairs = readPairsCsv(bag_output + "/pairs.csv");
  // The last scans wait for the encoder reading after theirs; the node concludes them, as
  // calibrate_bag does at the end of its bag, once every input has been silent for
  // ~silent_topic_timeout_s (5 s).
  PairsFile node_pairs;
  waitFor(
      [&] {
        try {
          node_pairs = readPairsCsv(output_directory + "/pairs.csv");
        } catch (const std::exception&) {
          return false;  // a row being appended
        }
        return node_pairs.pairs.size() >= bag_pairs.pairs.size() &&
               pairs_seen >= bag_pairs.pairs.size();
      },
      15.0);
  ASSERT_EQ(node_pairs.pairs.size(), bag_pairs.pairs.size());
  EXPECT_EQ(node_pairs.pairs.size(), pairs_seen);
  for (std::size_t i = 0; i < bag_pairs.pairs.size(); ++i) {
    const MotionPair& a = node_pairs.pairs[i];
    const MotionPair& b = bag_pairs.pairs[i];
    ASSERT_DOUBLE_EQ(a.start_stamp_s, b.start_stamp_s) << "pair " << i;
    ASSERT_DOUBLE_EQ(a.end_stamp_s, b.end_stamp_s) << "pair " << i;
    ASSERT_LE((a.sensor_motion.vector() - b.sensor_motion.vector()).norm(),
              1e-6 * (1.0 + b.sensor_motion.vector().norm()))
        << "pair " << i;
    ASSERT_EQ(a.encoder_samples.size(), b.encoder_samples.size()) << "pair " << i;
  }
  odometry_calibration::Calibrate full;
  full.request.model = "diff_drive";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", full));
  ASSERT_TRUE(full.response.success) << full.response.message;
  const YAML::Node result = YAML::LoadFile(bag_output + "/result.yaml");
  for (const auto& parameter : full.response.report.parameters) {
    const double expected = result["parameters"][parameter.name]["value"].as<double>();
    EXPECT_NEAR(parameter.value, expected, 1e-6 * std::max(1.0, std::abs(expected)))
        << parameter.name;
  }
  fs::remove_all(output_directory);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_replay_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
