#include "odometry_calibration/common/config_schema.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// The value as the user wrote it: a scalar's text, anything else as YAML flow text.
std::string shown(const YAML::Node& node)
{
  if (node.IsScalar())
    return node.Scalar().empty() ? "\"\"" : node.Scalar();
  if (node.IsNull())
    return "(no value)";
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

[[noreturn]] void refuse(const ConfigKeySpec& spec, const std::string& key,
                         const std::string& value, const std::string& problem)
{
  throw std::runtime_error(key + ": " + value + " " + problem +
                           "; allowed: " + describeAllowed(spec));
}

std::string formatNumber(double value)
{
  if (value == std::floor(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  char text[32];
  const auto result = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, result.ptr);
}

std::string describeRange(const ConfigRange& range, const std::string& unit)
{
  const double huge = std::numeric_limits<double>::max();
  std::string text;
  if (range.min == -huge && range.max == huge)
    text = "any finite number";
  else if (range.max == huge)
    text = (range.min_open ? "> " : ">= ") + formatNumber(range.min);
  else if (range.min == -huge)
    text = (range.max_open ? "< " : "<= ") + formatNumber(range.max);
  else
    text = (range.min_open ? "in (" : "in [") + formatNumber(range.min) + ", " +
           formatNumber(range.max) + (range.max_open ? ")" : "]");
  return unit.empty() ? text : text + " " + unit;
}

std::string joined(const std::vector<std::string>& words, const char* separator)
{
  std::string text;
  for (const std::string& word : words)
    text += (text.empty() ? "" : separator) + (word.empty() ? "\"\"" : word);
  return text;
}

bool readBool(const YAML::Node& node, const ConfigKeySpec& spec, const std::string& key)
{
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
    refuse(spec, key, shown(node), "is not true or false");
  return value;
}

double readNumber(const YAML::Node& node, const ConfigKeySpec& spec, const std::string& key)
{
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value))
    refuse(spec, key, shown(node), "is not a number");
  if (!std::isfinite(value))
    refuse(spec, key, shown(node), "is not a finite number");
  if (!spec.range.contains(value))
    refuse(spec, key, shown(node), "is out of range");
  if (!spec.values.empty()) {
    bool listed = false;
    for (double allowed : spec.values)
      listed = listed || value == allowed;
    if (!listed)
      refuse(spec, key, shown(node), "is not an allowed value");
  }
  return value;
}

long long readInteger(const YAML::Node& node, const ConfigKeySpec& spec, const std::string& key)
{
  const std::string text = node.IsScalar() ? node.Scalar() : std::string();
  long long value = 0;
  const char* begin = text.c_str() + (text.rfind('+', 0) == 0 ? 1 : 0);
  const auto result = std::from_chars(begin, text.c_str() + text.size(), value);
  if (text.empty() || result.ptr != text.c_str() + text.size()) {
    double number = 0.0;
    const bool is_number = node.IsScalar() && YAML::convert<double>::decode(node, number);
    refuse(spec, key, shown(node), is_number ? "is not an integer" : "is not a number");
  }
  if (result.ec != std::errc() || !spec.range.contains(static_cast<double>(value)))
    refuse(spec, key, shown(node), "is out of range");
  return value;
}

std::string readString(const YAML::Node& node, const ConfigKeySpec& spec, const std::string& key)
{
  if (!node.IsScalar())
    refuse(spec, key, shown(node), "is not a string");
  const std::string value = node.Scalar();
  if (value.empty() && !spec.allow_empty)
    refuse(spec, key, shown(node), "is empty");
  if (!spec.choices.empty()) {
    bool listed = false;
    for (const std::string& choice : spec.choices)
      listed = listed || value == choice;
    if (!listed)
      refuse(spec, key, "'" + value + "'", "is not one of the choices");
  }
  return value;
}

/// A list's elements, each read as a scalar of the list's element type.
ConfigValue readList(const YAML::Node& node, const ConfigKeySpec& spec, const std::string& key)
{
  if (!node.IsSequence())
    refuse(spec, key, shown(node), "is not a list");
  if (node.size() < spec.min_size || node.size() > spec.max_size)
    refuse(spec, key, shown(node), "has " + std::to_string(node.size()) + " elements");
  if (spec.type == ConfigType::kStringList) {
    std::vector<std::string> values;
    for (std::size_t i = 0; i < node.size(); ++i)
      values.push_back(readString(node[i], spec, key + "[" + std::to_string(i) + "]"));
    return values;
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(readNumber(node[i], spec, key + "[" + std::to_string(i) + "]"));
    if (spec.increasing && i > 0 && !(values[i] > values[i - 1]))
      refuse(spec, key, shown(node), "must increase");
  }
  return values;
}

bool isSectionOf(const std::vector<std::string>& keys, const std::string& prefix)
{
  for (const std::string& key : keys) {
    if (key.rfind(prefix, 0) == 0)
      return true;
  }
  return false;
}

/// The known keys directly below `prefix` (for the message of an unknown key).
std::string knownBelow(const std::vector<std::string>& keys, const std::string& prefix)
{
  std::set<std::string> names;
  for (const std::string& key : keys) {
    if (!prefix.empty() && key.rfind(prefix + ".", 0) != 0)
      continue;
    const std::string rest = prefix.empty() ? key : key.substr(prefix.size() + 1);
    names.insert(rest.substr(0, std::min(rest.find('.'), rest.find('['))));
  }
  std::string text;
  for (const std::string& name : names)
    text += " " + name;
  return text;
}

}  // namespace

bool ConfigRange::contains(double value) const
{
  const bool above = min_open ? value > min : value >= min;
  const bool below = max_open ? value < max : value <= max;
  return above && below;
}

ConfigValue readConfigValue(const YAML::Node& node, const ConfigKeySpec& spec,
                            const std::string& key)
{
  switch (spec.type) {
    case ConfigType::kBool:
      return readBool(node, spec, key);
    case ConfigType::kInt:
      return readInteger(node, spec, key);
    case ConfigType::kDouble:
      return readNumber(node, spec, key);
    case ConfigType::kString:
      return readString(node, spec, key);
    case ConfigType::kDoubleList:
    case ConfigType::kStringList:
      return readList(node, spec, key);
  }
  throw std::logic_error("readConfigValue: unknown type");
}

std::string describeAllowed(const ConfigKeySpec& spec)
{
  std::string element;
  if (!spec.choices.empty()) {
    element = "one of: " + joined(spec.choices, ", ");
  } else if (!spec.values.empty()) {
    std::vector<std::string> values;
    for (double value : spec.values)
      values.push_back(formatNumber(value));
    element = joined(values, " or ");
  } else if (spec.type == ConfigType::kBool) {
    return "true or false";
  } else if (spec.type == ConfigType::kString || spec.type == ConfigType::kStringList) {
    element = spec.allow_empty ? "any string" : "a non-empty string";
  } else {
    element = (spec.type == ConfigType::kInt ? "an integer " : "a number ") +
              describeRange(spec.range, spec.unit);
  }
  if (spec.type != ConfigType::kDoubleList && spec.type != ConfigType::kStringList)
    return element;
  const std::string size = spec.min_size == spec.max_size ? std::to_string(spec.min_size)
                                                          : std::to_string(spec.min_size) + " to " +
                                                                std::to_string(spec.max_size);
  return "a list of " + size + ", each " + element + (spec.increasing ? ", increasing" : "");
}

std::string formatConfigValue(const ConfigValue& value)
{
  struct Formatter
  {
    std::string operator()(bool v) const { return v ? "true" : "false"; }
    std::string operator()(long long v) const { return std::to_string(v); }
    std::string operator()(double v) const { return formatNumber(v); }
    std::string operator()(const std::string& v) const
    {
      // Plain when YAML reads the text back as the same string, double-quoted otherwise.
      bool plain = !v.empty() && v.find_first_of(":#,[]{}&*!|>'\"%@`") == std::string::npos;
      try {
        const YAML::Node read = plain ? YAML::Load(v) : YAML::Node();
        plain = plain && read.IsScalar() && read.Scalar() == v;
      } catch (const YAML::Exception&) {
        plain = false;
      }
      YAML::Emitter out;
      out << YAML::DoubleQuoted << v;
      return plain ? v : out.c_str();
    }
    std::string operator()(const std::vector<double>& v) const
    {
      std::vector<std::string> words;
      for (double x : v)
        words.push_back(formatNumber(x));
      return "[" + joined(words, ", ") + "]";
    }
    std::string operator()(const std::vector<std::string>& v) const
    {
      std::vector<std::string> words;
      for (const std::string& x : v)
        words.push_back((*this)(x));
      return "[" + joined(words, ", ") + "]";
    }
  };
  return std::visit(Formatter{}, value);
}

std::string formatConfigDefault(const ConfigKeySpec& spec)
{
  return spec.default_value ? formatConfigValue(*spec.default_value) : spec.default_text;
}

void refuseDuplicateKeys(const YAML::Node& node, const std::string& prefix)
{
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      refuseDuplicateKeys(node[i], prefix + "[" + std::to_string(i) + "]");
    return;
  }
  if (!node.IsMap())
    return;
  std::set<std::string> seen;
  for (const auto& entry : node) {
    const std::string name = entry.first.IsScalar() ? entry.first.Scalar() : shown(entry.first);
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    if (!seen.insert(name).second) {
      throw std::runtime_error(key +
                               ": the key appears twice in one mapping (YAML would silently use "
                               "only one of them); keep one");
    }
    refuseDuplicateKeys(entry.second, key);
  }
}

void refuseUnknownKeys(const YAML::Node& node, const std::vector<std::string>& keys,
                       const std::string& prefix)
{
  if (!node.IsMap())
    throw std::runtime_error((prefix.empty() ? "the document" : prefix) + ": expected a map");
  const std::string pattern = [&prefix] {
    std::string p = prefix;
    for (std::size_t open = p.find('['); open != std::string::npos; open = p.find('[', open + 2))
      p.erase(open + 1, p.find(']', open) - open - 1);
    return p;
  }();
  for (const auto& entry : node) {
    const std::string name = entry.first.IsScalar() ? entry.first.Scalar() : shown(entry.first);
    const std::string key = pattern.empty() ? name : pattern + "." + name;
    const std::string shown_key = prefix.empty() ? name : prefix + "." + name;
    bool leaf = false;
    for (const std::string& known : keys)
      leaf = leaf || known == key;
    if (leaf)
      continue;
    if (isSectionOf(keys, key + ".")) {
      refuseUnknownKeys(entry.second, keys, shown_key);
    } else if (isSectionOf(keys, key + "[].")) {
      if (!entry.second.IsSequence())
        throw std::runtime_error(shown_key + ": expected a list");
      for (std::size_t i = 0; i < entry.second.size(); ++i)
        refuseUnknownKeys(entry.second[i], keys, shown_key + "[" + std::to_string(i) + "]");
    } else {
      throw std::runtime_error((prefix.empty() ? std::string() : prefix + ": ") + "unknown key '" +
                               name + "' (known:" + knownBelow(keys, pattern) + ")");
    }
  }
}

YAML::Node findConfigNode(const YAML::Node& root, const std::string& key)
{
  YAML::Node node = root;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string name = key.substr(start, dot == std::string::npos ? dot : dot - start);
    if (!node.IsMap())
      return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& parent = node;  // const: a lookup must not add the key
    YAML::Node child = parent[name];
    if (!child || dot == std::string::npos)
      return child;
    node.reset(child);
    start = dot + 1;
  }
}

}  // namespace odometry_calibration
