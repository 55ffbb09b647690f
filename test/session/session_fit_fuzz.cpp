// Fuzz target: a configuration and per-call options (`~calibrate`'s, after a `---8<---` line)
// into the session's fit on a small simulated pair set (issue 32: the configuration target
// stopped at the parsed settings, and a start radius of 1e308 crashed the fit's covariance).
#include <cstdint>
#include <stdexcept>

#include "odometry_calibration/session/session_fit.h"
#include "odometry_calibration/sim/pair_generator.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

namespace {

/// 12 s of the default simulated differential drive, pairs every 0.5 s (left_wheel,
/// right_wheel, as the shipped diff_drive.yaml names them).
const std::vector<MotionPair>& simulatedPairs()
{
  static const std::vector<MotionPair> pairs = [] {
    sim::PairGeneratorOptions options;
    options.duration_s = 12.0;
    options.interval_s = 0.5;
    return sim::generatePairs(options).pairs;
  }();
  return pairs;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const auto [config_text, options_text] = test::splitFuzzText(test::fuzzText(data, size));
  try {
    SessionFitRequest request;
    request.config = parseCalibrationConfig(config_text, "fuzz.yaml");
    if (!options_text.empty()) {
      request.config.models =
          configForModel(config_text, request.config.model, options_text, "fuzz.yaml").models;
    }
    request.pairs = simulatedPairs();
    fitSessionPairs(request);
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
