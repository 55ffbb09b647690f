// A comparison's TUM trajectories (eval/tum_trajectory.h) written into a folder of their own,
// for score_calibration (calibrate_bag writes them with its result set, result_files.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace odometry_calibration {

/// Creates `directory` if needed and writes each (name, content) into it atomically (a file is
/// whole or absent). Returns the names written, comma-separated, for the terminal. Throws
/// std::runtime_error naming the path that cannot be written.
std::string writeTrajectoryFiles(const std::string& directory,
                                 const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace odometry_calibration
