#include "odometry_calibration/models/joint_fit_report.h"

#include <algorithm>
#include <cmath>

namespace odometry_calibration {

double aloneIntrinsicsSpread(const JointFitReport& report)
{
  double spread = 0.0;
  for (std::size_t i = 0; i < report.intrinsics.size(); ++i) {
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    for (const ModelReport& alone : report.alone) {
      if (alone.parameters.size() <= i || alone.parameters[i].name != report.intrinsics[i].name)
        return std::numeric_limits<double>::quiet_NaN();
      low = std::min(low, alone.parameters[i].value);
      high = std::max(high, alone.parameters[i].value);
    }
    if (report.alone.size() > 1)
      spread = std::max(spread, (high - low) / std::abs(report.intrinsics[i].value));
  }
  return spread;
}

ModelReport sensorModelReport(const JointFitReport& report, std::size_t index)
{
  const JointSensorReport& sensor = report.sensors.at(index);
  ModelReport one;
  one.model = report.model;
  one.parameters = report.intrinsics;
  one.parameters.insert(one.parameters.end(), sensor.pose.begin(), sensor.pose.end());
  one.parameters.insert(one.parameters.end(), report.derived.begin(), report.derived.end());
  one.before = index < report.alone.size() ? report.alone[index].before : ResidualRms();
  one.after = sensor.after;
  one.residual_rms_xytheta = sensor.residual_rms_xytheta;
  one.pairs_used = sensor.pairs;
  one.outliers = sensor.outliers;
  one.rejected = sensor.rejected;
  one.down_weighted = sensor.outliers - sensor.rejected;
  one.iterations = report.iterations;
  one.converged = report.converged;
  one.termination = report.termination;
  one.fit_time_s = report.fit_time_s;
  one.has_extrinsic = true;
  one.T_base_sensor = sensor.T_base_sensor;
  one.warnings = sensor.warnings;
  one.notes = sensor.notes;
  return one;
}

}  // namespace odometry_calibration
