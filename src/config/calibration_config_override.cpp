#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/config_schema.h"
#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/config/calibration_config.h"

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

/// The configuration's and the options' YAML (an empty options text is an empty mapping), each
/// without a duplicated key (merging would hide it).
std::pair<YAML::Node, YAML::Node> loadBoth(const std::string& config_text,
                                           const std::string& override_yaml,
                                           const std::string& source)
{
  YAML::Node root = loadYamlDocument(config_text, source);
  YAML::Node overrides;
  try {
    refuseDuplicateKeys(root);
  } catch (const std::runtime_error& error) {  // also YAML::Exception
    throw std::runtime_error(source + ": " + error.what());
  }
  try {
    overrides = YAML::Load(override_yaml);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error("options are not YAML: " + std::string(error.what()));
  }
  refuseYamlBeyond(overrides, "options");
  try {
    refuseDuplicateKeys(overrides);
  } catch (const std::runtime_error& error) {
    throw std::runtime_error("options: " + std::string(error.what()));
  }
  if (overrides.IsNull())
    overrides = YAML::Node(YAML::NodeType::Map);
  if (!overrides.IsMap())
    throw std::runtime_error("options must be a YAML mapping, e.g. {gp: {kernel: linear}}");
  return {root, overrides};
}

/// `root` with the allowed sections of `overrides` merged in, parsed and validated.
CalibrationConfig merged(YAML::Node root, const YAML::Node& overrides, const std::string& source)
{
  static const std::set<std::string> allowed = {"diff_drive",    "linear",  "gp",
                                                "tricycle",      "mecanum", "skid_steer",
                                                "base_odometry", "model",   "prior_model"};
  for (const auto& entry : overrides) {
    const std::string key = entry.first.as<std::string>();
    if (allowed.count(key) == 0) {
      throw std::runtime_error("options: '" + key +
                               "' cannot be changed per call (allowed: diff_drive, tricycle, "
                               "mecanum, skid_steer, base_odometry, linear, gp, model, "
                               "prior_model)");
    }
  }
  mergeInto(root, overrides);
  std::ostringstream text;
  text << root;
  return parseCalibrationConfig(text.str(), source);
}

}  // namespace

CalibrationConfig overrideModelOptions(const std::string& config_text,
                                       const std::string& override_yaml, const std::string& source)
{
  auto [root, overrides] = loadBoth(config_text, override_yaml, source);
  return merged(root, overrides, overrides.size() > 0 ? source + " + options" : source);
}

CalibrationConfig configForModel(const std::string& config_text, const std::string& model,
                                 const std::string& override_yaml, const std::string& source)
{
  auto [root, overrides] = loadBoth(config_text, override_yaml, source);
  const std::string where =
      source + " (model " + model + (overrides.size() > 0 ? ", with options)" : ")");
  overrides["model"] = model;
  return merged(root, overrides, where);
}

}  // namespace odometry_calibration
