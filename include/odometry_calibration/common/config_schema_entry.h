// A configuration key's declaration bound to a field of the struct it fills (the calibration
// configuration's in calibration_config_schema.cpp): ConfigSchemaEntry and the builders of its
// usual kinds. `field` is a callable giving a reference to the field for a const or non-const
// target, e.g. [](auto& c) -> auto& { return c.keyframe_interval_s; }.
#pragma once

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "odometry_calibration/common/config_schema.h"

namespace odometry_calibration {

/// One key: its declaration; `set` stores a value read for it (empty for a key whose default
/// depends on other keys: the reader resolves those); `get` gives the value a target holds.
template <typename Target>
struct ConfigSchemaEntry
{
  using Setter = std::function<void(Target&, const ConfigValue&)>;
  using Getter = std::function<ConfigValue(const Target&)>;

  ConfigKeySpec spec;
  Setter set;
  Getter get;
};

/// [min, max]
inline ConfigRange rangeClosed(double min, double max)
{
  return {min, max, false, false};
}

/// (min, max)
inline ConfigRange rangeOpen(double min, double max)
{
  return {min, max, true, true};
}

/// A declaration with its key, type, unit and description (the rest: ConfigKeySpec's defaults).
inline ConfigKeySpec configKeySpec(const std::string& key, ConfigType type, const char* unit,
                                   const char* description)
{
  ConfigKeySpec s;
  s.key = key;
  s.type = type;
  s.unit = unit;
  s.description = description;
  return s;
}

template <typename Target, typename Field>
ConfigSchemaEntry<Target> number(const std::string& key, double value, const char* unit,
                                 ConfigRange range, const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{configKeySpec(key, ConfigType::kDouble, unit, description), {}, {}};
  e.spec.range = range;
  e.spec.default_value = value;
  e.set = [field](Target& t, const ConfigValue& v) { field(t) = std::get<double>(v); };
  e.get = [field](const Target& t) { return ConfigValue(static_cast<double>(field(t))); };
  return e;
}

template <typename Target, typename Field>
ConfigSchemaEntry<Target> integer(const std::string& key, long long value, ConfigRange range,
                                  const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{configKeySpec(key, ConfigType::kInt, "", description), {}, {}};
  e.spec.range = range;
  e.spec.default_value = value;
  e.set = [field](Target& t, const ConfigValue& v) {
    field(t) = static_cast<std::decay_t<decltype(field(t))>>(std::get<long long>(v));
  };
  e.get = [field](const Target& t) { return ConfigValue(static_cast<long long>(field(t))); };
  return e;
}

template <typename Target, typename Field>
ConfigSchemaEntry<Target> flag(const std::string& key, bool value, const char* description,
                               Field field)
{
  ConfigSchemaEntry<Target> e{configKeySpec(key, ConfigType::kBool, "", description), {}, {}};
  e.spec.default_value = value;
  e.set = [field](Target& t, const ConfigValue& v) { field(t) = std::get<bool>(v); };
  e.get = [field](const Target& t) { return ConfigValue(static_cast<bool>(field(t))); };
  return e;
}

template <typename Target, typename Field>
ConfigSchemaEntry<Target> text(const std::string& key, const char* value, bool allow_empty,
                               const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{configKeySpec(key, ConfigType::kString, "", description), {}, {}};
  e.spec.default_value = std::string(value);
  e.spec.allow_empty = allow_empty;
  e.set = [field](Target& t, const ConfigValue& v) { field(t) = std::get<std::string>(v); };
  e.get = [field](const Target& t) { return ConfigValue(field(t)); };
  return e;
}

/// A string among `choices` that sets an enum: `parse` turns the name into the value, `name`
/// the value into its name.
template <typename Target, typename Parse, typename Name>
ConfigSchemaEntry<Target> choice(const std::string& key, const char* value,
                                 std::vector<std::string> choices, const char* description,
                                 Parse parse, Name name)
{
  ConfigSchemaEntry<Target> e{configKeySpec(key, ConfigType::kString, "", description), {}, {}};
  e.spec.default_value = std::string(value);
  e.spec.choices = std::move(choices);
  e.set = [parse](Target& t, const ConfigValue& v) { parse(t, std::get<std::string>(v)); };
  e.get = [name](const Target& t) { return ConfigValue(std::string(name(t))); };
  return e;
}

/// A key whose default depends on other keys (`default_text`): the reader resolves it; `get`
/// gives the value a target holds.
template <typename Target>
ConfigSchemaEntry<Target> derivedEntry(ConfigKeySpec s, const char* default_text,
                                       std::function<ConfigValue(const Target&)> get)
{
  s.default_text = default_text;
  return ConfigSchemaEntry<Target>{std::move(s), {}, std::move(get)};
}

/// Appends `more` to `entries`.
template <typename Target>
void appendEntries(std::vector<ConfigSchemaEntry<Target>>& entries,
                   std::vector<ConfigSchemaEntry<Target>> more)
{
  for (ConfigSchemaEntry<Target>& entry : more)
    entries.push_back(std::move(entry));
}

}  // namespace odometry_calibration
