// Fuzz target: the simulator's scenario YAML (with a shipped world) and world YAML (after a
// "---8<---" line), then a few rays cast in the world.
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/world.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const auto [scenario_text, world_text] = test::splitFuzzText(test::fuzzText(data, size));
  try {
    sim::loadScenarioYaml(test::fuzzFile(scenario_text, ".yaml"),
                          ODOMETRY_CALIBRATION_CONFIG_DIR "/sim/worlds");
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  } catch (const YAML::Exception&) {
  }
  if (world_text.empty())
    return 0;
  try {
    const sim::World world = sim::parseWorldYaml(world_text, "world.yaml");
    for (int k = 0; k < 8; ++k) {
      world.castRay(Eigen::Vector2d(0.5, 0.25), k * M_PI / 4.0, 30.0);
      world.isFree(Eigen::Vector2d(k * 0.5, -k * 0.25));
      world.clearance(Eigen::Vector2d(k * 0.5, 1.0));
    }
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  } catch (const YAML::Exception&) {
  }
  return 0;
}
