#include "odometry_calibration/common/name_list.h"

namespace odometry_calibration {

std::string quotedNames(const std::vector<std::string>& names)
{
  if (names.empty())
    return "none";
  std::string text;
  for (const std::string& name : names)
    text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

}  // namespace odometry_calibration
