// generate_pairs: keyframe pairs with a known truth from a simulator scenario, as a pairs file.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/sim/pair_generator.h"
#include "odometry_calibration/sim/scenario.h"

namespace {

const char* kUsage =
    "usage: generate_pairs SCENARIO.yaml --output PAIRS.csv [options]\n"
    "\n"
    "Runs the scenario's robot (its robot, laser pose, encoders rate, motion, duration, seed)\n"
    "in an open field and writes keyframe pairs: the encoder samples of each interval and the\n"
    "true sensor displacement plus Gaussian noise of the given sigma (no scan matching).\n"
    "\n"
    "options:\n"
    "  --interval S        keyframe spacing [s] (default 0.3)\n"
    "  --noise-m M         sigma of the x, y noise [m] (default 0.002)\n"
    "  --noise-rad R       sigma of the heading noise [rad] (default 0.002)\n"
    "  --seed N            override the scenario's seed\n"
    "  --duration S        override the scenario's duration [s]\n";

}  // namespace

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  std::string scenario_path, output;
  sim::PairGeneratorOptions options;
  double seed = -1.0, duration = -1.0;
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      if (arg == "-h" || arg == "--help") {
        std::cout << kUsage;
        return 0;
      }
      if (arg[0] != '-') {
        scenario_path = arg;
        continue;
      }
      if (i + 1 >= args.size())
        throw std::invalid_argument("option " + arg + " needs a value");
      const std::string& value = args[++i];
      if (arg == "--output") {
        output = value;
      } else if (arg == "--interval") {
        options.interval_s = parseNumberArgument(arg, value, 0.0);
      } else if (arg == "--noise-m") {
        options.translation_noise_m = parseNumberArgument(arg, value, 0.0);
      } else if (arg == "--noise-rad") {
        options.rotation_noise_rad = parseNumberArgument(arg, value, 0.0);
      } else if (arg == "--seed") {
        seed = parseNumberArgument(arg, value, 0.0);
      } else if (arg == "--duration") {
        duration = parseNumberArgument(arg, value, 0.0);
      } else {
        throw std::invalid_argument("unknown option '" + arg + "'");
      }
    }
    if (scenario_path.empty() || output.empty()) {
      throw std::invalid_argument("give a scenario and --output");
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const sim::Scenario scenario = sim::loadScenarioYaml(
        scenario_path, std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds");
    options.robot = scenario.robot;
    options.T_base_sensor = scenario.laser.T_base_laser;
    options.motion = scenario.motion;
    options.encoder_rate_hz = scenario.encoders.rate_hz;
    options.duration_s = duration > 0.0 ? duration : scenario.duration_s;
    options.seed = seed >= 0.0 ? static_cast<unsigned>(seed) : scenario.seed;
    const sim::GeneratedPairs generated = sim::generatePairs(options);
    writePairsCsv(output, {generated.joints, generated.pairs});
    std::cout << "wrote " << generated.pairs.size() << " pairs to " << output << "\n";
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
