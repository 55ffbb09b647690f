// rostest (test/node_time_offset.test): the deformed demo robot (encoders 0.15 s ahead of the
// laser) replayed through the live node with estimate_time_offset on. ~calibrate estimates the
// offset itself with calibrate_bag's estimator (issue 18): within 0.01 s of the truth, equal to
// calibrate_bag's on the same bag within the node's sigma, and used for the pairs after the fit.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/CalibrationPair.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test::waitFor;

const std::string kNode = "/odometry_calibration";

TEST(NodeTimeOffset, CalibrateEstimatesTheOffsetLikeTheBagTool)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, config, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("config", config));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const YAML::Node truth = YAML::LoadFile(bag.substr(0, bag.size() - 4) + "_truth.yaml");
  // The simulator stamps the encoders at true time + time_offset_s: tau is that offset.
  const double true_tau_s = truth["encoders"]["time_offset_s"].as<double>();
  ASSERT_NEAR(std::abs(true_tau_s), 0.15, 1e-9);

  std::size_t pairs_seen = 0;
  auto on_pair = [&](const odometry_calibration::CalibrationPair::ConstPtr&) { ++pairs_seen; };
  ros::Subscriber s1 =
      handle.subscribe<odometry_calibration::CalibrationPair>(kNode + "/pairs", 1000, on_pair);
  ASSERT_TRUE(ros::service::waitForService(kNode + "/calibrate", ros::Duration(60)));
  ASSERT_TRUE(waitFor([&] { return test::nodeRunning("/player"); }, 30));
  ASSERT_TRUE(waitFor([&] { return !test::nodeRunning("/player"); }, 300));
  waitFor([] { return false; }, 2.0);  // the last messages

  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  const double tau_s = fit.response.report.time_offset_s;
  const std::size_t sentence = fit.response.message.find("tau = ");
  ASSERT_NE(sentence, std::string::npos) << fit.response.message;
  double reported_tau_s = 0.0, sigma_s = 0.0;
  ASSERT_EQ(std::sscanf(fit.response.message.c_str() + sentence, "tau = %lf +- %lf s",
                        &reported_tau_s, &sigma_s),
            2)
      << fit.response.message;
  // The estimate; the fit used it, or (within the 10 ms pairing tolerance) the offset the pairs
  // were made at, which the reply then says it kept.
  if (fit.response.message.find("were made at: kept") == std::string::npos)
    EXPECT_NEAR(reported_tau_s, tau_s, 1e-4) << fit.response.message;
  else
    EXPECT_NEAR(reported_tau_s, tau_s, 0.0101) << fit.response.message;
  EXPECT_GT(sigma_s, 0.0);
  EXPECT_LT(sigma_s, 0.01);
  EXPECT_NEAR(tau_s, true_tau_s, 0.01) << fit.response.message;

  // calibrate_bag on the same bag and configuration.
  const std::string bag_output = output_directory + "/calibrate_bag";
  ASSERT_TRUE(test::runCalibrateBag(config, bag, bag_output))
      << test::readText(bag_output + ".log");
  const YAML::Node result = YAML::LoadFile(bag_output + "/result.yaml");
  const double bag_tau_s = result["time_offset_s"].as<double>();
  EXPECT_LE(std::abs(tau_s - bag_tau_s), sigma_s)
      << "node " << tau_s << " s, calibrate_bag " << bag_tau_s << " s, sigma " << sigma_s;
  RecordProperty("node_tau_s", std::to_string(tau_s));
  RecordProperty("node_sigma_s", std::to_string(sigma_s));
  RecordProperty("bag_tau_s", std::to_string(bag_tau_s));
  std::printf("time offset: node %.4f +- %.4f s, calibrate_bag %.4f s, truth %.4f s\n", tau_s,
              sigma_s, bag_tau_s, true_tau_s);
  fs::remove_all(output_directory);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_time_offset_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
