#include "odometry_calibration/common/text_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {

std::string readTextFile(const std::string& path, const std::string& what)
{
  std::ifstream file(path);
  if (!file)
    throw std::runtime_error("cannot read " + what + " '" + path + "'");
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace odometry_calibration
