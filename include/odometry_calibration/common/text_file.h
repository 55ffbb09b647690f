// Reading a whole text file (configurations, results).
#pragma once

#include <string>

namespace odometry_calibration {

/// The file's content. `what` names the file's role, e.g. "the configuration". Throws
/// std::runtime_error with a message of its own for each reason it cannot be read:
/// "<path> does not exist: give the path of the configuration file", "<path> is a directory,
/// not a configuration file", "<path> is a named pipe, not a configuration file: ..." (a
/// socket, a device: anything but a regular file, which could block or never end), "cannot read the
/// configuration <path>: <system error>" (e.g. permission denied) and "<path> is empty: the
/// configuration file holds nothing to read".
std::string readTextFile(const std::string& path, const std::string& what);

}  // namespace odometry_calibration
