// The joint fit of several sensors in words: one table per sensor (the shared wheel
// parameters and its pose with σ, its pairs, residuals and observability verdict), then the
// consistency figure: the wheel parameters each sensor implies fitted alone, side by side.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/models/joint_fit_report.h"

namespace odometry_calibration {

/// The joint fit's text: a formatModelReport per sensor (sensorModelReport, titled with
/// `sensor_names[s]`), then the table of the fits alone against the joint values with the
/// largest relative spread. `sensor_names` has one name per sensor.
std::string formatJointFitReport(const JointFitReport& report,
                                 const std::vector<std::string>& sensor_names);

/// The table of the fits alone: one row per intrinsic parameter with the joint value, each
/// sensor's value alone (± σ) and their relative spread [%].
std::string formatAloneAgreement(const JointFitReport& report,
                                 const std::vector<std::string>& sensor_names);

}  // namespace odometry_calibration
