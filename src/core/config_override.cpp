#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/pipeline/calibration_config.h"

namespace odometry_calibration {
namespace {

/// Copies `from` into `into` key by key (maps merge recursively, anything else replaces).
void mergeInto(YAML::Node into, const YAML::Node& from)
{
  for (const auto& entry : from) {
    const std::string key = entry.first.as<std::string>();
    if (entry.second.IsMap() && into[key] && into[key].IsMap()) {
      mergeInto(into[key], entry.second);
    } else {
      into[key] = YAML::Clone(entry.second);
    }
  }
}

}  // namespace

CalibrationConfig overrideModelOptions(const std::string& config_text,
                                       const std::string& override_yaml, const std::string& source)
{
  YAML::Node root, overrides;
  try {
    root = YAML::Load(config_text);
    overrides = YAML::Load(override_yaml);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error("options are not YAML: " + std::string(error.what()));
  }
  if (overrides.IsNull())
    return parseCalibrationConfig(config_text, source);
  if (!overrides.IsMap())
    throw std::runtime_error("options must be a YAML mapping, e.g. {gp: {kernel: linear}}");
  static const std::set<std::string> allowed = {"diff_drive", "linear", "gp", "model",
                                                "prior_model"};
  for (const auto& entry : overrides) {
    const std::string key = entry.first.as<std::string>();
    if (allowed.count(key) == 0) {
      throw std::runtime_error("options: '" + key +
                               "' cannot be changed per call (allowed: diff_drive, linear, gp, "
                               "model, prior_model)");
    }
  }
  mergeInto(root, overrides);
  std::ostringstream merged;
  merged << root;
  return parseCalibrationConfig(merged.str(), source + " + options");
}

}  // namespace odometry_calibration
