// The effective configuration as commented YAML, and the README's table, from the schema.
#include <sstream>

#include "odometry_calibration/config/calibration_config_schema.h"

namespace odometry_calibration {
namespace {

/// The parts of a full key: "ego_motion.cloud.band_m" -> {ego_motion, cloud, band_m}.
std::vector<std::string> keyParts(const std::string& key)
{
  std::vector<std::string> parts;
  std::istringstream in(key);
  for (std::string part; std::getline(in, part, '.');)
    parts.push_back(part);
  return parts;
}

/// "description; allowed: ... (with the unit); default: ..." for the comment of a key.
std::string comment(const ConfigKeySpec& spec)
{
  return spec.description + "; allowed: " + describeAllowed(spec) +
         "; default: " + formatConfigDefault(spec);
}

/// Whether `value` is one the key allows (a model's joint names are not resolved, and show as
/// none, when the configuration does not use the model).
bool allowed(const std::string& value, const ConfigKeySpec& spec)
{
  try {
    readConfigValue(YAML::Load(value), spec, spec.key);
    return true;
  } catch (const std::runtime_error&) {
    return false;
  }
}

/// "<indent><name>: <value>" padded, then "# <comment>"; the key commented out when the
/// configuration holds no value for it.
void writeLine(std::ostringstream& out, std::size_t depth, const std::string& name,
               const std::string& value, const ConfigKeySpec& spec)
{
  const bool unset = !allowed(value, spec);
  std::string line = std::string(2 * depth, ' ') + (unset ? "# " : "") + name + ": " +
                     (unset ? "(unused)" : value);
  if (line.size() < 40)
    line.resize(40, ' ');
  out << line << "  # " << comment(spec) << "\n";
}

void writeJoints(std::ostringstream& out, const CalibrationConfig& config)
{
  out << "joints:\n";
  for (const JointConfig& joint : config.joints) {
    bool first = true;
    for (const auto& entry : jointConfigSchema()) {
      const std::string name = entry.spec.key.substr(entry.spec.key.find("].") + 2);
      writeLine(out, 1, (first ? "- " : "  ") + name, formatConfigValue(entry.get(joint)),
                entry.spec);
      first = false;
    }
  }
}

/// ego_motion.sources at `depth`: each source's keys (a time offset left to
/// keyframes.time_offset_s commented out), or, without the list, its keys commented out.
void writeSources(std::ostringstream& out, const CalibrationConfig& config, std::size_t depth)
{
  if (config.ego_motion_sources.empty()) {  // the keys shown, commented out: one source below
    out << std::string(2 * depth, ' ')
        << "# sources:  (one source: source, scan_topic, topic, publisher)\n";
    for (const auto& entry : sourceConfigSchema()) {
      const std::string name = entry.spec.key.substr(entry.spec.key.find("].") + 2);
      out << std::string(2 * depth + 2, ' ') << "# " << name << ": (unused)  # "
          << comment(entry.spec) << "\n";
    }
    return;
  }
  out << std::string(2 * depth, ' ') << "sources:\n";
  for (const EgoMotionSourceConfig& source : config.ego_motion_sources) {
    bool first = true;
    for (const auto& entry : sourceConfigSchema()) {
      const std::string name = entry.spec.key.substr(entry.spec.key.find("].") + 2);
      writeLine(out, depth + 1, (first ? "- " : "  ") + name, formatConfigValue(entry.get(source)),
                entry.spec);
      first = false;
    }
  }
}

/// Whether `key` is one of the one-source keys that ego_motion.sources replaces.
bool replacedBySources(const CalibrationConfig& config, const std::string& key)
{
  return !config.ego_motion_sources.empty() &&
         (key == "ego_motion.source" || key == "ego_motion.scan_topic" ||
          key == "ego_motion.topic" || key == "ego_motion.publisher");
}

}  // namespace

std::string formatEffectiveConfig(const CalibrationConfig& config)
{
  std::ostringstream out;
  out << "# The effective calibration configuration: every key with its value; the comments say\n"
         "# what it is, the values allowed (with the unit) and the default\n"
         "# (calibration_config_schema.h).\n";
  writeJoints(out, config);
  std::vector<std::string> open;  // the sections written last
  for (const auto& entry : calibrationConfigSchema()) {
    std::vector<std::string> parts = keyParts(entry.spec.key);
    const std::string name = parts.back();
    parts.pop_back();
    std::size_t common = 0;
    while (common < open.size() && common < parts.size() && open[common] == parts[common])
      ++common;
    for (std::size_t depth = common; depth < parts.size(); ++depth) {
      out << std::string(2 * depth, ' ') << parts[depth] << ":\n";
      if (depth == 0 && parts[0] == "ego_motion")
        writeSources(out, config, 1);
    }
    open = parts;
    if (replacedBySources(config, entry.spec.key)) {
      out << std::string(2 * parts.size(), ' ') << "# " << name
          << ": (replaced by ego_motion.sources)\n";
      continue;
    }
    writeLine(out, parts.size(), name, formatConfigValue(entry.get(config)), entry.spec);
  }
  return out.str();
}

std::string formatConfigSchemaMarkdown()
{
  static const char* const kTypes[] = {"bool",   "int",         "double",
                                       "string", "double list", "string list"};
  std::ostringstream out;
  out << "| key | type | default | unit | allowed | meaning |\n"
      << "|---|---|---|---|---|---|\n";
  for (const ConfigKeySpec* spec : calibrationConfigSpecs()) {
    const std::string default_text =
        spec->default_value ? "`" + formatConfigDefault(*spec) + "`" : formatConfigDefault(*spec);
    out << "| `" << spec->key << "` | " << kTypes[static_cast<int>(spec->type)] << " | "
        << default_text << " | " << spec->unit << " | " << describeAllowed(*spec) << " | "
        << spec->description << " |\n";
  }
  return out.str();
}

}  // namespace odometry_calibration
