// Whether this build has PCL. The 3D cloud input (cloud_to_scan.h: the ego-motion source type
// 'cloud') and the kd-tree correspondence search (nearest_point_search.h) need it; CMakeLists.txt
// leaves them out when PCL is not found (scripts/demo installs only what the 2D tools need) and
// writes ODOMETRY_CALIBRATION_HAVE_PCL, 1 or 0, into the generated pcl_build.h (in the devel
// space's include folder). What asks for them in a build without PCL is refused with
// withoutPclMessage().
#pragma once

#include <string>

#include "odometry_calibration/scan/pcl_build.h"

namespace odometry_calibration {

/// True when the build found PCL (and pcl_conversions): clouds and the kd-tree are built.
inline constexpr bool kHavePcl = ODOMETRY_CALIBRATION_HAVE_PCL != 0;

/// The refusal of `what` (e.g. "ego_motion.source: cloud (PointCloud2 on '/points')") in a
/// build without PCL: what is missing and how to get it.
std::string withoutPclMessage(const std::string& what);

}  // namespace odometry_calibration
