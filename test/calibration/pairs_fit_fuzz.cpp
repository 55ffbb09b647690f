// Fuzz target: a pairs file into every model's fit (issue 32: the reader alone never reached
// the fits). The pairs (at most 80) are fitted with each model the shipped configuration whose
// joints they carry allows: diff_drive.yaml (diff_drive, linear, gp, skid_steer), tricycle.yaml
// and mecanum.yaml.
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/factory/model_factory.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

namespace {

struct Shipped
{
  CalibrationConfig config;
  std::vector<std::string> models;
};

const std::vector<Shipped>& shipped()
{
  static const std::vector<Shipped> configs = [] {
    const std::string dir = ODOMETRY_CALIBRATION_CONFIG_DIR;
    std::vector<Shipped> loaded;
    for (const auto& [file, models] : std::vector<std::pair<std::string, std::vector<std::string>>>{
             {"diff_drive.yaml", {"diff_drive", "linear", "gp", "skid_steer"}},
             {"tricycle.yaml", {"tricycle"}},
             {"mecanum.yaml", {"mecanum"}}}) {
      for (const std::string& model : models) {
        const std::string text = readTextFile(dir + "/" + file, "the configuration");
        loaded.push_back({configForModel(text, model, "", file), {model}});
      }
    }
    return loaded;
  }();
  return configs;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream input(test::fuzzText(data, size));
  PairsFile file;
  try {
    file = parsePairsCsv(input, "pairs.csv");
  } catch (const std::runtime_error&) {
    return 0;
  }
  if (file.pairs.size() > 80)
    file.pairs.resize(80);
  for (const Shipped& entry : shipped()) {
    if (jointLayout(entry.config).names != file.joints.names)
      continue;
    try {
      makeModel(entry.models.front(), entry.config.models)->fit(file.pairs);
    } catch (const std::invalid_argument&) {
    } catch (const std::runtime_error&) {
    }
  }
  return 0;
}
