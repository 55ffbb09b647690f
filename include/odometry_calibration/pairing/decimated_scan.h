// Every k-th ray of a scan: the cheaper scans of the consecutive-scan chain, which only checks
// the keyframe matches (pair_collector.h, CollectorOptions::consecutive_max_rays).
#pragma once

#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// Rays 0, stride, 2 stride, ... of `scan`, with its angle spacing and time increment times
/// `stride`, and its validity mask, ray times and ray bearings (when given) taken at the same
/// rays: each kept ray keeps its bearing, reading and time. stride 1 copies the scan. Throws
/// std::invalid_argument for stride < 1.
Scan decimateRays(const Scan& scan, int stride);

}  // namespace odometry_calibration
