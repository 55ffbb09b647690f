// generate_pairs: keyframe pairs with a known truth from a simulator scenario, as a pairs file.
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
  std::vector<std::string> scenario_paths;
  std::string output;
  sim::PairGeneratorOptions options;
  sim::ScenarioOverrides overrides;
  try {
    ArgumentParser parser;
    parser.option("--output", &output)
        .number("--interval", &options.interval_s, 0.0)
        .number("--noise-m", &options.translation_noise_m, 0.0)
        .number("--noise-rad", &options.rotation_noise_rad, 0.0)
        .number("--seed", &overrides.seed, 0.0)
        .number("--duration", &overrides.duration_s, 0.0)
        .positionals(&scenario_paths, 1);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (scenario_paths.empty() || output.empty()) {
      throw std::invalid_argument("give a scenario and --output");
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const sim::Scenario scenario =
        sim::loadScenarioYaml(scenario_paths[0], sim::shippedWorldsDirectory(), overrides);
    const sim::GeneratedPairs generated =
        sim::generatePairs(sim::pairGeneratorOptions(scenario, options));
    writePairsCsv(output, {generated.joints, generated.pairs});
    std::cout << "wrote " << generated.pairs.size() << " pairs to " << output << "\n";
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
