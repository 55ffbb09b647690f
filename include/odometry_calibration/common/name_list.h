// Names in messages for people: what the data has, listed beside what was asked for.
#pragma once

#include <string>
#include <vector>

namespace odometry_calibration {

/// The names quoted and separated by commas ("'a', 'b'"); "none" for no name.
std::string quotedNames(const std::vector<std::string>& names);

}  // namespace odometry_calibration
