// End-to-end: a base that publishes only its own odometry (nav_msgs/Odometry on /odom) with a
// 3 % translation and a 2 % rotation scale error, beside a laser, on the simulated office drive.
// calibrate_bag with config/base_odometry.yaml (model base_odometry, wheels.source odometry)
// recovers both multipliers within 0.1 % and the laser's pose within 5 mm and 0.3 deg, and,
// scored with --test on a second drive, the corrected odometry's ATE is within 1.2 times the
// ATE of the diff_drive fit to the same drive's JointState. The linear model and the GP take
// the base's increments as their inputs (rows of the same table).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_tools/bag_calibration.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/score_table.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
constexpr double kTranslationError = 0.03, kRotationError = 0.02;

using test_support::scoreTableRow;

/// calibrate_bag's exit status and text.
struct ToolRun
{
  int status = -1;
  std::string text;
};

ToolRun calibrate(const std::string& config_path, const std::string& bag,
                  const std::string& test_bag, const std::string& output_dir)
{
  BagCalibrationOptions options;
  options.config_path = config_path;
  options.bags = {bag};
  options.test_bags = {test_bag};
  options.output_dir = output_dir;
  options.quiet = true;
  std::ostringstream out;
  ToolRun run;
  try {
    run.status = calibrateBags(options, out);
    run.text = out.str();
  } catch (const std::exception& error) {
    run.status = 1;
    run.text = out.str() + "error: " + error.what();
  }
  return run;
}

/// `text` with `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to)
{
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

TEST(CalibrateBagBaseOdometry, ScalesSensorPoseAndAteAgainstTheJointStateFit)
{
  char pattern[] = "/tmp/calibrate_bag_base_odometry_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office.yaml",
                                                 kConfig + "/sim/worlds");
  scenario.duration_s = 60.0;
  scenario.seed = 46;
  scenario.encoders.output = "odometry";  // the JointState and the base's own odometry
  scenario.encoders.odometry_translation_error = kTranslationError;
  scenario.encoders.odometry_rotation_error = kRotationError;
  simulateToBag(scenario, directory + "/train.bag", "");
  scenario.seed = 47;
  simulateToBag(scenario, directory + "/test.bag", "");

  const std::string odometry_config = directory + "/base_odometry.yaml";
  std::ofstream(odometry_config) << readTextFile(kConfig + "/base_odometry.yaml", "config");
  const ToolRun odometry = calibrate(odometry_config, directory + "/train.bag",
                                     directory + "/test.bag", directory + "/odometry_out");
  ASSERT_TRUE(odometry.status == 0 || odometry.status == 4) << odometry.text;
  const YAML::Node result = YAML::LoadFile(directory + "/odometry_out/result.yaml");
  const YAML::Node parameters = result["parameters"];
  const double k_t = parameters["translation_scale"]["value"].as<double>();
  const double k_r = parameters["rotation_scale"]["value"].as<double>();
  const Pose2& truth = scenario.laser.T_base_laser;
  const double dx = parameters["sensor_x"]["value"].as<double>() - truth.x();
  const double dy = parameters["sensor_y"]["value"].as<double>() - truth.y();
  const double dtheta = parameters["sensor_theta"]["value"].as<double>() - truth.theta();
  std::cout << "translation_scale " << k_t << " (truth " << 1.0 / (1.0 + kTranslationError) << ", "
            << 100.0 * std::abs(k_t * (1.0 + kTranslationError) - 1.0) << " % off), rotation_scale "
            << k_r << " (truth " << 1.0 / (1.0 + kRotationError) << ", "
            << 100.0 * std::abs(k_r * (1.0 + kRotationError) - 1.0)
            << " % off), sensor pose off by " << 1000.0 * std::hypot(dx, dy) << " mm, "
            << dtheta * 180.0 / M_PI << " deg\n";
  EXPECT_LT(std::abs(k_t * (1.0 + kTranslationError) - 1.0), 1e-3);
  EXPECT_LT(std::abs(k_r * (1.0 + kRotationError) - 1.0), 1e-3);
  EXPECT_LT(std::hypot(dx, dy), 0.005);
  EXPECT_LT(std::abs(dtheta), 0.3 * M_PI / 180.0);

  // The same drive's JointState, fitted by diff_drive and scored on the same test drive.
  std::string wheels = readTextFile(kConfig + "/diff_drive.yaml", "config");
  wheels = replaced(wheels, "compare_models: [linear, gp]", "compare_models: []");
  const std::string wheel_config = directory + "/diff_drive.yaml";
  std::ofstream(wheel_config) << wheels;
  const ToolRun joint_state = calibrate(wheel_config, directory + "/train.bag",
                                        directory + "/test.bag", directory + "/wheels_out");
  ASSERT_TRUE(joint_state.status == 0 || joint_state.status == 4) << joint_state.text;
  const std::vector<double> corrected = scoreTableRow(odometry.text, "base_odometry");
  const std::vector<double> uncorrected = scoreTableRow(odometry.text, "nominal");
  const std::vector<double> wheel_fit = scoreTableRow(joint_state.text, "diff_drive");
  ASSERT_EQ(corrected.size(), 5u) << odometry.text;
  ASSERT_EQ(uncorrected.size(), 5u) << odometry.text;
  ASSERT_EQ(wheel_fit.size(), 5u) << joint_state.text;
  std::cout << "test-drive ATE: base_odometry " << corrected[0] << " m, the base's own odometry "
            << uncorrected[0] << " m, diff_drive on the JointState " << wheel_fit[0] << " m (ratio "
            << corrected[0] / wheel_fit[0] << ")\n";
  EXPECT_LT(corrected[0], 1.2 * wheel_fit[0]) << odometry.text << joint_state.text;
  EXPECT_GT(uncorrected[0], 3.0 * corrected[0]) << odometry.text;  // the scales mattered
  // The model-free fits take the base's increments too.
  EXPECT_EQ(scoreTableRow(odometry.text, "linear").size(), 5u) << odometry.text;
  EXPECT_EQ(scoreTableRow(odometry.text, "gp").size(), 5u) << odometry.text;
}

}  // namespace
}  // namespace odometry_calibration
