// The calibration result as YAML: parameters with sigma, the sensor extrinsic, fit quality.
#pragma once

#include <string>

#include "odometry_calibration/eval/tricycle_report.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// YAML document with the calibrated parameters (value, sigma, initial, unit), the sensor pose
/// in base_link, residuals, pair counts, solver summary, trajectory errors and warnings.
/// `source` names the data the fit used. With `validation`, also the keyframe interval (and its
/// validation curve when chosen) and the held-out errors.
std::string tricycleResultToYaml(const TricycleCalibrationResult& result,
                                 const TricycleEvaluation& evaluation, const std::string& source,
                                 const TricycleValidation* validation = nullptr);

}  // namespace odometry_calibration
