// Every key of the calibration configuration (calibration_config.h), declared once: type,
// default, unit, allowed range, a one-line description, where its value goes in
// CalibrationConfig and how the effective configuration shows it. The parser, the unknown-key
// check, the range checks, `calibrate_bag --print-config` and the README's configuration table
// (checked by the calibration_config_schema test) all come from these declarations.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/common/config_schema.h"

namespace odometry_calibration {

/// One key: its declaration; `set` stores a value read for it (empty for the keys whose
/// default depends on other keys, e.g. a model's joint names: the parser resolves those from the
/// values read); `get` gives the value a configuration holds.
template <typename Target>
struct ConfigSchemaEntry
{
  ConfigKeySpec spec;
  std::function<void(Target&, const ConfigValue&)> set;
  std::function<ConfigValue(const Target&)> get;
};

/// The keys of one entry of `joints` ("joints[].name", ...), in the README's order.
const std::vector<ConfigSchemaEntry<JointConfig>>& jointConfigSchema();

/// Every other key ("joint_state_topic", "keyframes.interval_s", ...), section by section.
const std::vector<ConfigSchemaEntry<CalibrationConfig>>& calibrationConfigSchema();

/// Every declaration, the joints' first.
std::vector<const ConfigKeySpec*> calibrationConfigSpecs();

/// The effective configuration as YAML that parseCalibrationConfig reads back to the same
/// values, each key commented with its description, unit, allowed range and default.
std::string formatEffectiveConfig(const CalibrationConfig& config);

/// The README's configuration table (Markdown): key, type, default, unit, allowed, meaning.
std::string formatConfigSchemaMarkdown();

}  // namespace odometry_calibration
