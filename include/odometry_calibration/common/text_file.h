// Reading a whole text file (configurations, results).
#pragma once

#include <string>

namespace odometry_calibration {

/// The file's content. Throws std::runtime_error "cannot read <what> '<path>'".
std::string readTextFile(const std::string& path, const std::string& what);

}  // namespace odometry_calibration
