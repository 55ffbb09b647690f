// Writes the Mines rover log (datasets/mines_log.h) as a rosbag: sensor_msgs/JointState on
// /joint_states (left_wheel, right_wheel: cumulative ticks) and sensor_msgs/LaserScan on /scan
// (682 rays, frame "laser"), both stamped with the line's time.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/datasets/mines_log.h"

namespace odometry_calibration {

/// Writes one JointState and one LaserScan per record to `bag_path`, atomically: into
/// "<bag_path>.partial", renamed when complete and removed on an error. Throws
/// std::runtime_error for no record or a file that cannot be written or renamed.
void writeMinesBag(const std::vector<MinesRecord>& records, const std::string& bag_path);

}  // namespace odometry_calibration
