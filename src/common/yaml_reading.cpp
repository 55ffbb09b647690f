#include "odometry_calibration/common/yaml_reading.h"

#include <unordered_set>
#include <vector>

namespace odometry_calibration {

YAML::Node loadYamlDocument(const std::string& text, const std::string& source,
                            std::size_t max_nodes)
{
  YAML::Node root;
  try {
    // yaml-cpp makes an alias a reference to its anchored node, so parsing stays linear in
    // the text; it is every walk of the tree that expands the aliases.
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(source + ": " + error.what());
  }
  refuseYamlBeyond(root, source, max_nodes);
  return root;
}

void refuseYamlBeyond(const YAML::Node& root, const std::string& source, std::size_t max_nodes)
{
  // Walk the tree as its readers will (an alias once at each use), iteratively (no recursion
  // on a deep document), and stop at the bound. A node met again is recognised by where it
  // stands in the text and its type (a block map starts where its first key does): aliases are
  // the only way one node is reached twice.
  std::vector<YAML::Node> stack{root};
  std::unordered_set<std::size_t> positions;
  std::size_t visited = 0;
  bool repeated = false;
  while (!stack.empty()) {
    const YAML::Node node = stack.back();
    stack.pop_back();
    if (++visited > max_nodes) {
      if (repeated) {
        throw std::runtime_error(
            source + ": YAML aliases expand to more than " + std::to_string(max_nodes) +
            " nodes (the first " + std::to_string(max_nodes) + " are " +
            std::to_string(positions.size()) +
            " written ones repeated: an alias bomb?): write the values out instead of "
            "repeating anchors (&) through aliases (*)");
      }
      throw std::runtime_error(
          source + ": the document holds more than " + std::to_string(max_nodes) +
          " nodes: no file this program reads needs that many; check the path");
    }
    const auto position =
        static_cast<std::size_t>(node.Mark().pos + 1) * 8 + static_cast<std::size_t>(node.Type());
    repeated = !positions.insert(position).second || repeated;
    if (node.IsSequence()) {
      for (const YAML::Node& child : node)
        stack.push_back(child);
    } else if (node.IsMap()) {
      for (const auto& entry : node) {
        stack.push_back(entry.first);
        stack.push_back(entry.second);
      }
    }
  }
}

void rethrowWithYamlContext(const std::string& source, const std::string& where)
{
  try {
    throw;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(where + ": " + error.what());
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    throw std::runtime_error(message.rfind(source, 0) == 0 ? message : where + ": " + message);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(where + ": " + error.what());
  }
}

}  // namespace odometry_calibration
