// End-to-end: one simulated drive of the office robot published four ways (JointState
// positions; per-wheel std_msgs/Int16 tick topics with 8-bit and with 16-bit counters, the right
// wheel's messages 7 ms after the left's; velocity-only JointState), each calibrated by
// calibrate_bag's job with config/diff_drive.yaml plus its `wheels` section: the wheel
// parameters agree within 0.05 % across the inputs. A tick drive published too slowly for its
// 8-bit counters is refused, naming the key, the measured step and what to set.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_tools/bag_calibration.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/sim/scenario.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const char* kParameters[] = {"left_wheel_radius", "right_wheel_radius", "wheel_separation"};

/// One way of publishing the wheels: the simulator's encoder options and the configuration's
/// counter width and `wheels` section.
struct WheelInput
{
  std::string name;
  std::string output;  ///< encoders.output
  int counter_bits = 32;
  std::string wheels_yaml;  ///< appended to the configuration
  BagFormat format = BagFormat::kRos1;
};

const std::string kTicksYaml =
    "\nwheels:\n  source: ticks\n  topics: [/left_wheel_ticks, /right_wheel_ticks]\n"
    "  message_type: std_msgs/Int16\n";

/// A run of one input: calibrate_bag's exit status, its text and result.yaml's parameters.
struct InputRun
{
  int status = -1;
  std::string text;
  std::map<std::string, double> parameters;
  sim::SimulationSummary summary;
};

class CalibrateBagWheels : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/calibrate_bag_wheels_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }

  /// The office drive (60 s, seed 46) published as `input`, then calibrated; `rate_hz` > 0
  /// replaces the encoders' rate.
  static InputRun run(const WheelInput& input, double rate_hz = 0.0)
  {
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 60.0;
    scenario.seed = 46;
    scenario.encoders.output = input.output;
    scenario.encoders.counter_bits = input.counter_bits;
    scenario.encoders.tick_type = "std_msgs/Int16";
    scenario.encoders.tick_stagger_s = 0.007;
    if (rate_hz > 0.0)
      scenario.encoders.rate_hz = rate_hz;
    InputRun result;
    const std::string bag =
        directory_ + "/" + input.name + (input.format == BagFormat::kRos1 ? ".bag" : "");
    result.summary = simulateToBag(scenario, bag, "", nullptr, input.format);
    std::string config = readTextFile(kConfig + "/diff_drive.yaml", "the configuration");
    const std::string bits = "counter_bits: " + std::to_string(input.counter_bits);
    for (std::size_t at = config.find("counter_bits: 32"); at != std::string::npos;
         at = config.find("counter_bits: 32", at + bits.size()))
      config.replace(at, 16, bits);
    config.replace(config.find("compare_models: [linear, gp]"), 28, "compare_models: []");
    const std::string config_path = directory_ + "/" + input.name + ".yaml";
    std::ofstream(config_path) << config << input.wheels_yaml;
    BagCalibrationOptions options;
    options.config_path = config_path;
    options.bags = {bag};
    options.output_dir = directory_ + "/out_" + input.name;
    options.quiet = true;
    std::ostringstream out;
    try {
      result.status = calibrateBags(options, out);
      result.text = out.str();
    } catch (const std::exception& error) {  // calibrate_bag's exit status 1 and its message
      result.status = 1;
      result.text = out.str() + "error: " + error.what();
    }
    if (result.status == 0 || result.status == 4) {
      const YAML::Node parameters =
          YAML::LoadFile(options.output_dir + "/result.yaml")["parameters"];
      for (const char* name : kParameters)
        result.parameters[name] = parameters[name]["value"].as<double>();
    }
    return result;
  }

  static std::string directory_;
};

std::string CalibrateBagWheels::directory_;

TEST_F(CalibrateBagWheels, JointStateTicksAndVelocitiesGiveTheSameWheelsWithin005Percent)
{
  const InputRun positions = run({"joint_state", "joint_state", 32, ""});
  ASSERT_TRUE(positions.status == 0 || positions.status == 4) << positions.text;
  const WheelInput others[] = {
      {"ticks8", "ticks", 8, kTicksYaml},
      {"ticks16", "ticks", 16, kTicksYaml},
      {"joint_velocity", "joint_velocity", 32, "\nwheels:\n  source: joint_velocity\n"},
      {"ticks8_db3", "ticks", 8, kTicksYaml, BagFormat::kDb3},
  };
  for (const WheelInput& input : others) {
    const InputRun other = run(input);
    ASSERT_TRUE(other.status == 0 || other.status == 4) << input.name << "\n" << other.text;
    if (input.output == "ticks") {  // the counters wrapped: the unwrapping was exercised
      EXPECT_GT(other.summary.counter_wraps, input.counter_bits == 8 ? 400u : 0u) << input.name;
    }
    for (const char* name : kParameters) {
      const double reference = positions.parameters.at(name);
      const double relative = std::abs(other.parameters.at(name) - reference) / reference;
      std::cout << input.name << " " << name << ": " << other.parameters.at(name) << " vs "
                << reference << " (" << 100.0 * relative << " %)\n";
      EXPECT_LT(relative, 5e-4) << input.name << " " << name;
    }
  }
  // And the truth is near (the scenario's 0.0765 m and 0.0775 m wheels, 0.32 m apart).
  EXPECT_NEAR(positions.parameters.at("left_wheel_radius"), 0.0765, 0.0005);
  EXPECT_NEAR(positions.parameters.at("right_wheel_radius"), 0.0775, 0.0005);
  EXPECT_NEAR(positions.parameters.at("wheel_separation"), 0.32, 0.003);
}

TEST_F(CalibrateBagWheels, EightBitTicksPublishedTooSlowlyAreRefusedNamingTheKey)
{
  // 5 Hz: about 400 ticks between two messages at full speed, more than half of 256.
  const InputRun slow = run({"ticks8_slow", "ticks", 8, kTicksYaml}, 5.0);
  EXPECT_EQ(slow.status, 1) << slow.text;
  EXPECT_NE(slow.text.find("aliases"), std::string::npos) << slow.text;
  EXPECT_NE(slow.text.find("].counter_bits to the counter's real width or publish the ticks "
                           "faster"),
            std::string::npos)
      << slow.text;
}

}  // namespace
}  // namespace odometry_calibration
