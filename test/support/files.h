// Reading a whole file in tests (outputs of the tools, written bags): the bytes, or "" when the
// file cannot be opened (tests assert on the content, so a missing file shows there).
#pragma once

#include <fstream>
#include <iterator>
#include <string>

namespace odometry_calibration {
namespace test_support {

inline std::string readFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

}  // namespace test_support
}  // namespace odometry_calibration
