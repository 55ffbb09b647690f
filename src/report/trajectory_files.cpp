#include "odometry_calibration/report/trajectory_files.h"

#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/common/atomic_file.h"

namespace odometry_calibration {

std::string writeTrajectoryFiles(const std::string& directory,
                                 const std::vector<std::pair<std::string, std::string>>& files)
{
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory)) {
    throw std::runtime_error("cannot create the trajectory folder '" + directory +
                             "': " + (error ? error.message() : "a file has that name"));
  }
  std::string written;
  for (const auto& [name, content] : files) {
    writeFileAtomically(directory + "/" + name, content);
    written += (written.empty() ? "" : ", ") + directory + "/" + name;
  }
  return written;
}

}  // namespace odometry_calibration
