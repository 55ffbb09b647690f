// The node's custom messages from core types: a fit report and a calibration pair.
#pragma once

#include <string>

#include "odometry_calibration/CalibrationPair.h"
#include "odometry_calibration/CalibrationReport.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {
namespace ros_conversions {

/// The report of a fit over `pairs_collected` pairs at time offset `time_offset_s` [s].
odometry_calibration::CalibrationReport toReportMsg(const ModelReport& report,
                                                    std::size_t pairs_collected,
                                                    double time_offset_s);

/// A pair with its features (increments of incremental joints, means of absolute ones).
odometry_calibration::CalibrationPair toPairMsg(const MotionPair& pair, const JointLayout& joints,
                                                const std::string& sensor_frame);

}  // namespace ros_conversions
}  // namespace odometry_calibration
