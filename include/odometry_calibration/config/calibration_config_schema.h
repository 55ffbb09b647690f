// Every key of the calibration configuration (calibration_config.h), declared once: type,
// default, unit, allowed range, a one-line description, where its value goes in
// CalibrationConfig and how the effective configuration shows it. The parser, the unknown-key
// check, the range checks, `calibrate_bag --print-config` and the README's configuration table
// (checked by the calibration_config_schema test) all come from these declarations.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/common/config_schema_entry.h"
#include "odometry_calibration/config/calibration_config.h"

namespace odometry_calibration {

/// The keys of one entry of `joints` ("joints[].name", ...), in the README's order.
const std::vector<ConfigSchemaEntry<JointConfig>>& jointConfigSchema();

/// The keys of one entry of `ego_motion.sources` ("ego_motion.sources[].topic", ...).
const std::vector<ConfigSchemaEntry<EgoMotionSourceConfig>>& sourceConfigSchema();

/// Every other key ("joint_state_topic", "keyframes.interval_s", ...), section by section.
const std::vector<ConfigSchemaEntry<CalibrationConfig>>& calibrationConfigSchema();

/// The keys of the model sections (diff_drive, tricycle, mecanum, skid_steer, linear, gp): the
/// last part of calibrationConfigSchema().
const std::vector<ConfigSchemaEntry<CalibrationConfig>>& modelConfigSchema();

/// The keys of the `gyro:` section (calibration_config_schema_gyro.cpp): part of
/// calibrationConfigSchema(), before the models'.
const std::vector<ConfigSchemaEntry<CalibrationConfig>>& gyroConfigSchema();

/// Every declaration, the joints' first, then the ego-motion sources'.
std::vector<const ConfigKeySpec*> calibrationConfigSpecs();

/// The effective configuration as YAML that parseCalibrationConfig reads back to the same
/// values, each key commented with its description, unit, allowed range and default.
std::string formatEffectiveConfig(const CalibrationConfig& config);

/// The README's configuration table (Markdown): key, type, default, unit, allowed, meaning.
std::string formatConfigSchemaMarkdown();

}  // namespace odometry_calibration
