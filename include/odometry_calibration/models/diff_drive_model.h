// Differential-drive calibration (wheel radii, wheel separation, sensor pose) by robust
// nonlinear least squares on keyframe pairs: the paper's CMLE baseline model.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/diff_drive_kinematics.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/sensor_motion_state.h"

namespace odometry_calibration {

/// Options of the differential-drive model.
struct DiffDriveOptions
{
  DiffDriveEncoderLayout layout;         ///< which joints are the wheels, ticks per turn
  double initial_left_radius_m = 0.05;   ///< start value of r_L [m]
  double initial_right_radius_m = 0.05;  ///< start value of r_R [m]
  double initial_separation_m = 0.3;     ///< start value of b [m]
  Pose2 initial_T_base_sensor;           ///< start value of the sensor pose
  double huber_threshold = 3.0;          ///< Huber threshold on a pair's whitened error [sigma]
  int max_iterations = 500;              ///< Levenberg-Marquardt iteration cap (per solve)
  /// Global starts: sensor yaws tried, evenly spaced from the start value (8: every 45 deg);
  /// 1 = only the start value.
  int yaw_starts = 8;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const DiffDriveOptions& options);

/// The wheels among `joints`: the joint named `left_joint` (`right_joint`), or, for an empty
/// name, the first (second) incremental joint. Throws std::invalid_argument "no joint named
/// '<name>' in the pairs" or "diff_drive needs two incremental joints".
DiffDriveEncoderLayout diffDriveLayoutForJoints(const JointLayout& joints,
                                                const std::string& left_joint,
                                                const std::string& right_joint,
                                                double ticks_per_turn);

/// What the diff_drive fit's observability verdict says each parameter needs.
ObservabilityHints diffDriveObservabilityHints();

/// Whether intrinsics (r_L, r_R, b) are the mirrored, unphysical solution: (-r_L, -r_R, -b) with
/// the sensor at (-x, -y, theta + pi) predicts the same motions; the physical one has positive
/// radii.
bool diffDriveMirrored(const Eigen::Vector3d& intrinsics);

/// The numbers a diff_drive model saves besides the sensor pose, each key once: the wheel joints
/// and the intrinsics (the fitted ones when written, the start values when read back); also the
/// tracked model's (tracked_model.h), which adds its separation growth.
template <class Layout, class Number, class Visit>
void visitDiffDriveYaml(Layout& layout, Number& left_radius_m, Number& right_radius_m,
                        Number& separation_m, const Visit& visit)
{
  visit("left_index", layout.left_index);
  visit("right_index", layout.right_index);
  visit("ticks_per_turn", layout.ticks_per_turn);
  visit("left_wheel_radius_m", left_radius_m);
  visit("right_wheel_radius_m", right_radius_m);
  visit("wheel_separation_m", separation_m);
}

/// The fitted model: intrinsics (r_L, r_R, b), the sensor's pose, and their 6x6 covariance.
class DiffDriveModel : public MotionModel
{
public:
  explicit DiffDriveModel(DiffDriveOptions options);

  std::string name() const override { return "diff_drive"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static DiffDriveModel fromYaml(const std::string& text);

  /// (r_L, r_R, b) [m].
  const Eigen::Vector3d& intrinsics() const { return state_.intrinsics; }
  const Pose2& T_base_sensor() const { return state_.T_base_sensor; }
  const DiffDriveOptions& options() const { return options_; }  ///< its joints, start values
  /// Covariance of (r_L, r_R, b, x, y, theta); zero until a fit succeeds.
  const Eigen::Matrix<double, 6, 6>& covariance() const { return state_.covariance; }

private:
  DiffDriveOptions options_;
  SensorMotionState<kDiffDriveParameterCount> state_;
};

}  // namespace odometry_calibration
