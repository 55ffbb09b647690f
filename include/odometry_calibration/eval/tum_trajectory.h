// Trajectories as files for other tools: the TUM RGB-D format that evo reads (`evo_ape tum
// reference.tum estimate.tum`): one pose per line, "t x y z qx qy qz qw", t in seconds, x y z
// in metres, (qx, qy, qz, qw) a unit quaternion. A planar pose (x, y, theta) is (x, y, 0) with
// the rotation theta about z: q = (0, 0, sin(theta/2), cos(theta/2)).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// The poses in TUM format, one line each. Throws std::invalid_argument when the sizes differ,
/// a value is not finite, or the stamps do not increase strictly (evo matches poses by stamp).
std::string tumTrajectoryText(const std::vector<double>& stamps_s, const std::vector<Pose2>& poses);

/// A sensor trajectory (sensor poses in the sensor frame of the first pose) as base_link's:
/// B_k = T_bs S_k T_bs^-1, base_link's poses in its frame at the first pose.
std::vector<Pose2> baseTrajectory(const std::vector<Pose2>& sensor_poses,
                                  const Pose2& T_base_sensor);

/// The TUM files of a comparison table's scored rows (file name, content): for each row not
/// skipped `<model>.sensor.tum` (its chained predictions in the sensor frame) and, when the row
/// knows the sensor's pose, `<model>.base_link.tum`; the chained scan matches of the first row
/// as `scan_matched.tum`, and `<model>.scan_matched.tum` for a row scored on other keyframes
/// (the nominal robot's pairs re-cut at time offset 0 may lose some).
std::vector<std::pair<std::string, std::string>> tumTrajectoryFiles(
    const std::vector<ModelScore>& scores);

}  // namespace odometry_calibration
