// Fuzz target: the calibration configuration YAML, with per-call option overrides (the node's
// ~calibrate `options`) after a "---8<---" line, and what the node derives from it.
#include <cstdint>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/config/calibration_config.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const auto [config_text, options] = test::splitFuzzText(test::fuzzText(data, size));
  try {
    const CalibrationConfig config = parseCalibrationConfig(config_text, "fuzz.yaml");
    encoderChannels(config);
    jointLayout(config);
    priorModel(config);
    priorPredictor(config);
    priorSensorPose(config);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  } catch (const YAML::Exception&) {
  }
  if (!options.empty()) {
    for (const char* model : {"", "diff_drive", "tricycle", "mecanum", "linear", "gp"}) {
      try {
        if (*model == '\0')
          overrideModelOptions(config_text, options, "fuzz.yaml");
        else
          configForModel(config_text, model, options, "fuzz.yaml");
      } catch (const std::runtime_error&) {
      } catch (const std::invalid_argument&) {
      } catch (const YAML::Exception&) {
      }
    }
  }
  return 0;
}
