// The generic half of a declared configuration schema: each key declared once with its type,
// default, unit, allowed range and a one-line description (ConfigKeySpec); a YAML value read
// and checked against it, with messages that name the full key, the value and what is allowed;
// unknown and duplicated keys refused. The calibration configuration's keys are in
// config/calibration_config_schema.h.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {

/// The type of a configuration value.
enum class ConfigType
{
  kBool,
  kInt,
  kDouble,
  kString,
  kDoubleList,
  kStringList,
};

/// The allowed interval of a number (and of each number of a list); an open end excludes its
/// bound. The default allows every finite number.
struct ConfigRange
{
  double min = -std::numeric_limits<double>::max();
  double max = std::numeric_limits<double>::max();
  bool min_open = false;
  bool max_open = false;

  /// Whether `value` lies in the interval (NaN never does).
  bool contains(double value) const;
};

/// A value of any ConfigType (kInt as long long).
using ConfigValue = std::variant<bool, long long, double, std::string, std::vector<double>,
                                 std::vector<std::string>>;

/// One key of a configuration.
struct ConfigKeySpec
{
  /// The full key: sections joined by '.', the entries of a list of maps as "joints[].name".
  std::string key;
  ConfigType type = ConfigType::kDouble;
  std::string unit;                  ///< "s", "m", "rad", ... ("" without one)
  ConfigRange range;                 ///< numbers and each number of a list
  std::vector<double> values;        ///< numbers: the only values allowed (e.g. 1, -1)
  std::vector<std::string> choices;  ///< strings and each string of a list (empty: any)
  bool allow_empty = true;           ///< strings: "" allowed
  std::size_t min_size = 0;          ///< lists: fewest elements
  std::size_t max_size = 64;         ///< lists: most elements
  bool increasing = false;           ///< lists of numbers: strictly increasing
  /// The value when the key is absent; nullopt when it depends on other keys (default_text).
  std::optional<ConfigValue> default_value;
  std::string default_text;  ///< the default in words when default_value is nullopt
  std::string description;   ///< one line
};

/// Reads `node` (the value of `key`, e.g. "joints[1].units_per_turn") as `spec` declares it.
/// Throws std::runtime_error "<key>: <value> ...; allowed: <describeAllowed>" for a value of
/// the wrong type, a number that is not finite or outside the range, a string not among the
/// choices, a list of the wrong size or order.
ConfigValue readConfigValue(const YAML::Node& node, const ConfigKeySpec& spec,
                            const std::string& key);

/// What `spec` allows, in words: "a number in [0.01, 60] s", "one of: scan, cloud",
/// "2 numbers, each in [-5, 5] s, increasing".
std::string describeAllowed(const ConfigKeySpec& spec);

/// `value` as YAML flow text: 0.5, true, /scan, "", [0.3, 0.5]; doubles with the fewest digits
/// that read back to the same double.
std::string formatConfigValue(const ConfigValue& value);

/// The default as the README shows it: formatConfigValue(default_value), or default_text.
std::string formatConfigDefault(const ConfigKeySpec& spec);

/// Throws std::runtime_error "<key>: the key appears twice ..." for a mapping anywhere in
/// `node` that holds a key twice (yaml-cpp would silently use one of them). `prefix` is the
/// key of `node` ("" for the document).
void refuseDuplicateKeys(const YAML::Node& node, const std::string& prefix = "");

/// Throws std::runtime_error "<section>: unknown key 'k' (known: ...)" for a key of `node`
/// (the document, or the section `prefix`) that is neither one of `keys` nor a section of
/// them, and "<section>: expected a map" for a section that is not one. `keys` are full keys
/// as in ConfigKeySpec::key; the entries of a list "x[]" must be maps of its keys.
void refuseUnknownKeys(const YAML::Node& node, const std::vector<std::string>& keys,
                       const std::string& prefix = "");

/// The node at a full key ("ego_motion.cloud.band_m") below `root`, or an invalid node.
YAML::Node findConfigNode(const YAML::Node& root, const std::string& key);

}  // namespace odometry_calibration
