// Small helpers for reading configuration YAML strictly: unknown keys are errors (a typo must
// not silently fall back to a default), optional keys keep their defaults.
#pragma once

#include <cstddef>
#include <set>
#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {

/// The most nodes a document read by loadYamlDocument may hold, each alias counted at every
/// place it is used. A configuration has a few hundred; a result.yaml, a scenario or a world a
/// few thousand (a world's walls); an alias bomb (anchors nested a few levels deep, each
/// repeating the one below ten times) expands to billions.
constexpr std::size_t kMaxYamlNodes = 100000;

/// `text` (the file or document `source`) parsed as YAML. Throws std::runtime_error
/// "<source>: YAML aliases expand to more than <max_nodes> nodes ..." when its nodes, aliases
/// expanded, number more than `max_nodes` (the walk stops at the bound, so an alias bomb is
/// refused at once instead of hanging every later walk of the document), "<source>: the
/// document holds more than <max_nodes> nodes" without aliases, and "<source>: <what>" for a
/// YAML syntax error.
YAML::Node loadYamlDocument(const std::string& text, const std::string& source,
                            std::size_t max_nodes = kMaxYamlNodes);

/// The bound of loadYamlDocument on a document parsed already (`root`, read from `source`).
void refuseYamlBeyond(const YAML::Node& root, const std::string& source,
                      std::size_t max_nodes = kMaxYamlNodes);

/// Throws std::runtime_error "<where>: unknown key 'k' (known: ...)" for a key not in
/// `allowed`, or "<where>: expected a map". An absent node is fine.
inline void checkYamlKeys(const YAML::Node& node, const std::set<std::string>& allowed,
                          const std::string& where)
{
  if (!node)
    return;
  if (!node.IsMap())
    throw std::runtime_error(where + ": expected a map");
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (allowed.count(key) == 0) {
      std::string known;
      for (const auto& name : allowed)
        known += " " + name;
      throw std::runtime_error(where + ": unknown key '" + key + "' (known:" + known + ")");
    }
  }
}

/// To be called in a catch (...) around the reading of a configuration file `source`:
/// rethrows the exception in flight as std::runtime_error "<where>: <what>", `where` being the
/// section that was being read (e.g. "<source>: keyframes"). A YAML::Exception or
/// std::invalid_argument always gets the prefix; another std::runtime_error only when its
/// message does not already start with `source`; any other exception is rethrown as it is.
[[noreturn]] void rethrowWithYamlContext(const std::string& source, const std::string& where);

/// Reads `node[key]` into `value` when present (yaml-cpp throws on a wrong type).
template <typename T>
void readYaml(const YAML::Node& node, const char* key, T* value)
{
  if (node && node[key])
    *value = node[key].as<T>();
}

}  // namespace odometry_calibration
