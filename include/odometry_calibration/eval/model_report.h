// Text and YAML forms of any model's fit report.
#pragma once

#include <string>

#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Human-readable report: parameters with sigma, residuals, pairs used / rejected, solver
/// summary, extrinsic, warnings.
std::string formatModelReport(const ModelReport& report);

/// YAML document: the report's numbers plus the fitted model (`model_yaml`, from toYaml()).
std::string modelResultYaml(const ModelReport& report, const std::string& model_yaml,
                            const std::string& source);

}  // namespace odometry_calibration
