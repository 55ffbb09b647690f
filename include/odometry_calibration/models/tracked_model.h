// The tracked base (tracked_kinematics.h): a differential drive whose effective separation
// grows with the turn's tightness, b(nu) = b0 + b1 nu, fitted with its wheel radii and the
// sensor's pose by the same robust least squares as the differential drive. Its start values
// and joints are the diff_drive section's (b1 starts at 0: the differential drive).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/tracked_kinematics.h"

namespace odometry_calibration {

/// left_wheel_radius, right_wheel_radius, wheel_separation (b0), separation_growth (b1) [m];
/// sensor_x, sensor_y [m], sensor_theta [rad].
const ParameterLayout& trackedParameters();

class TrackedModel : public MotionModel
{
public:
  /// The diff_drive options: joints, start values (b0 = initial_separation_m, b1 = 0), solver.
  explicit TrackedModel(DiffDriveOptions options);

  std::string name() const override { return "tracked"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static TrackedModel fromYaml(const std::string& text);

  /// (r_L, r_R, b0, b1) [m].
  const Eigen::Vector4d& intrinsics() const { return state_.intrinsics; }
  const Pose2& T_base_sensor() const { return state_.T_base_sensor; }
  /// The separation the base turns with at tightness nu in [0, 1]: b0 + b1 nu [m].
  double separationAt(double nu) const;

private:
  DiffDriveOptions options_;
  SensorMotionState<kTrackedParameterCount> state_;
};

}  // namespace odometry_calibration
