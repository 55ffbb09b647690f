// The motion coverage of a mecanum drive's pairs and the warnings naming what is missing.
#include <cmath>

#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/models/mecanum_model.h"

namespace odometry_calibration {

MecanumMotionCoverage mecanumMotionCoverage(const std::vector<MotionPair>& pairs,
                                            const MecanumEncoderLayout& layout,
                                            const Eigen::Matrix<double, 5, 1>& intrinsics)
{
  const int index[4] = {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
                        layout.rear_right_index};
  const double to_rad = 2.0 * M_PI / layout.ticks_per_turn;
  MecanumMotionCoverage coverage;
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2)
      continue;
    const EncoderSample& first = pair.encoder_samples.front();
    const EncoderSample& last = pair.encoder_samples.back();
    double d[4];
    for (int i = 0; i < 4; ++i)
      d[i] = std::abs(intrinsics(i)) * to_rad * (last.values(index[i]) - first.values(index[i]));
    // The three wheel patterns of mecanum_kinematics.h's forward kinematics.
    coverage.straight_m += std::abs(d[0] + d[1] + d[2] + d[3]) / 4.0;
    coverage.strafe_m += std::abs(-d[0] + d[1] + d[2] - d[3]) / 4.0;
    coverage.turn_rad +=
        std::abs(-d[0] + d[1] - d[2] + d[3]) / (4.0 * std::abs(intrinsics(kLxPlusLy)));
  }
  return coverage;
}

std::vector<std::string> mecanumMotionWarnings(const MecanumMotionCoverage& coverage)
{
  // Below these the pairs do not hold enough of a motion to separate what it determines.
  constexpr double kMinStraightM = 1.0;
  constexpr double kMinStrafeM = 1.0;
  constexpr double kMinTurnRad = 2.0;
  std::vector<std::string> warnings;
  if (coverage.strafe_m < kMinStrafeM) {
    warnings.push_back(
        "no strafing: the wheels moved the base only " + formatNumber(coverage.strafe_m) +
        " m sideways; the radii's diagonal difference (front left + rear right against front "
        "right + rear left) and sensor_theta are poorly separated without it; drive sideways "
        "both ways");
  }
  if (coverage.turn_rad < kMinTurnRad) {
    warnings.push_back(
        "no turning on the spot: the wheels turned the base only " +
        formatNumber(coverage.turn_rad) +
        " rad; lx_plus_ly, sensor_x and sensor_y are unobservable without turning; turn on the "
        "spot both ways");
  }
  if (coverage.straight_m < kMinStraightM) {
    warnings.push_back(
        "no driving straight: the wheels moved the base only " + formatNumber(coverage.straight_m) +
        " m forward or backward; the radii's common scale is fitted from sideways and turning "
        "motion alone; drive straight forward and backward");
  }
  return warnings;
}

}  // namespace odometry_calibration
