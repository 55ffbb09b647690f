#include "odometry_calibration/eval/joint_fit_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/eval/model_report.h"

namespace odometry_calibration {

std::string formatAloneAgreement(const JointFitReport& report,
                                 const std::vector<std::string>& sensor_names)
{
  std::string text = "\nwheel parameters each sensor implies alone (consistency):\n";
  char cell[160];
  std::snprintf(cell, sizeof(cell), "%-22s %12s", "parameter", "joint");
  text += cell;
  for (const std::string& name : sensor_names) {
    std::snprintf(cell, sizeof(cell), " %24s", (name + " alone").c_str());
    text += cell;
  }
  text += "   spread\n";
  for (std::size_t i = 0; i < report.intrinsics.size(); ++i) {
    const ParameterEstimate& joint = report.intrinsics[i];
    std::snprintf(cell, sizeof(cell), "%-22s %12.6g", joint.name.c_str(), joint.value);
    text += cell;
    double low = INFINITY, high = -INFINITY;
    for (const ModelReport& alone : report.alone) {
      const ParameterEstimate& own = alone.parameters.at(i);
      std::snprintf(cell, sizeof(cell), " %13.6g +- %-8.2g", own.value, own.sigma);
      text += cell;
      low = std::min(low, own.value);
      high = std::max(high, own.value);
    }
    std::snprintf(cell, sizeof(cell), " %7.3f %%\n", 100.0 * (high - low) / std::abs(joint.value));
    text += cell;
  }
  std::snprintf(cell, sizeof(cell), "largest spread of the fits alone: %.3f %% of the value\n",
                100.0 * aloneIntrinsicsSpread(report));
  return text + cell;
}

std::string formatJointFitReport(const JointFitReport& report,
                                 const std::vector<std::string>& sensor_names)
{
  if (sensor_names.size() != report.sensors.size() || report.alone.size() != report.sensors.size())
    throw std::invalid_argument("formatJointFitReport: one name and one fit alone per sensor");
  char line[300];
  std::snprintf(line, sizeof(line),
                "Joint fit of %zu sensors ('%s'): one set of wheel parameters, one pose per "
                "sensor, each pair weighted by its own covariance\n",
                report.sensors.size(), report.model.c_str());
  std::string text = line;
  for (std::size_t s = 0; s < report.sensors.size(); ++s) {
    std::snprintf(line, sizeof(line), "\nsensor %zu: %s (noise scale %.3g)\n", s,
                  sensor_names[s].c_str(), report.sensors[s].noise_scale);
    text += line + formatModelReport(sensorModelReport(report, s));
  }
  return text + formatAloneAgreement(report, sensor_names);
}

}  // namespace odometry_calibration
