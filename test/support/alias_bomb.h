// The "billion laughs" YAML for the readers' tests: anchors nested `levels` deep, each a list
// of ten aliases of the one before (10^levels nodes once expanded, a few hundred bytes
// written).
#pragma once

#include <string>

namespace odometry_calibration::test {

/// The document, as a mapping `<prefix>a0: &a0 [x, ...]`, `<prefix>a1: &a1 [*a0, ...]`, ...
/// after `head` (e.g. the keys a reader needs before it walks the rest).
inline std::string aliasBomb(int levels, const std::string& head = "")
{
  std::string text = head + "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < levels; ++level) {
    const std::string name = "a" + std::to_string(level);
    const std::string below = "*a" + std::to_string(level - 1);
    text += name + ": &" + name + " [";
    for (int i = 0; i < 10; ++i)
      text += (i > 0 ? ", " : "") + below;
    text += "]\n";
  }
  return text;
}

}  // namespace odometry_calibration::test
