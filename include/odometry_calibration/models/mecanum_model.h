// Four-wheel mecanum calibration (wheel radii, lx + ly, sensor pose) by robust nonlinear least
// squares on keyframe pairs: the parametric model of the GP paper's mecanum robot (Sec. IV, its
// ref. [16]; kinematics in mecanum_kinematics.h).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/pair_features.h"
#include "odometry_calibration/models/mecanum_kinematics.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/sensor_motion_state.h"

namespace odometry_calibration {

/// Options of the mecanum model.
struct MecanumOptions
{
  MecanumEncoderLayout layout;  ///< which joints are the wheels, ticks per turn
  /// Start values of r_FL, r_FR, r_RL, r_RR [m] (also the nominal model's radii).
  std::array<double, 4> initial_radius_m = {0.05, 0.05, 0.05, 0.05};
  double initial_lx_plus_ly_m = 0.35;  ///< start value of lx + ly [m]
  Pose2 initial_T_base_sensor;         ///< start value of the sensor pose
  double huber_threshold = 3.0;        ///< Huber threshold on a pair's whitened error [sigma]
  int max_iterations = 500;            ///< Levenberg-Marquardt iteration cap (per solve)
  /// Global starts: sensor yaws tried, evenly spaced from the start value (8: every 45 deg);
  /// 1 = only the start value.
  int yaw_starts = 8;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const MecanumOptions& options);

/// The wheels among `joints`: the joints named in `names` (front left, front right, rear left,
/// rear right), an empty name meaning the first, second, third, fourth incremental joint.
/// Throws std::invalid_argument "no joint named '<name>' in the pairs" or "mecanum needs four
/// incremental joints".
MecanumEncoderLayout mecanumLayoutForJoints(const JointLayout& joints,
                                            const std::array<std::string, 4>& names,
                                            double ticks_per_turn);

/// How much of each of the three motions of a mecanum base the pairs hold, from the wheels'
/// travel (nominal radii): driving straight (all wheels alike), strafing (FL, RR against FR,
/// RL) and turning (left wheels against right wheels). Sums of absolute values over the pairs.
struct MecanumMotionCoverage
{
  double straight_m = 0.0;  ///< forward/backward travel [m]
  double strafe_m = 0.0;    ///< sideways travel [m]
  double turn_rad = 0.0;    ///< heading change from the wheels [rad]
};

/// The coverage of `pairs` for the model's layout, radii and lx + ly.
MecanumMotionCoverage mecanumMotionCoverage(const std::vector<MotionPair>& pairs,
                                            const MecanumEncoderLayout& layout,
                                            const Eigen::Matrix<double, 5, 1>& intrinsics);

/// Warnings naming the motion the pairs lack for the mecanum parameters (no strafing: the
/// radii's diagonal pattern and the sensor yaw are confused; no turning: lx + ly and the sensor
/// position; no straight driving: the radii's common scale); empty when all three are there.
std::vector<std::string> mecanumMotionWarnings(const MecanumMotionCoverage& coverage);

/// What the mecanum fit's observability verdict says each parameter needs.
ObservabilityHints mecanumObservabilityHints();

/// Whether intrinsics (r_FL, r_FR, r_RL, r_RR, lx + ly) are the mirrored, unphysical solution:
/// all negated with the sensor at (-x, -y, theta + pi) predict the same motions; the physical
/// one has positive radii.
bool mecanumMirrored(const Eigen::Matrix<double, 5, 1>& intrinsics);

/// The fitted model: intrinsics (r_FL, r_FR, r_RL, r_RR, lx + ly), the sensor's pose, and their
/// 8x8 covariance. Unfitted, it predicts with the start values (the nominal robot).
class MecanumModel : public MotionModel
{
public:
  explicit MecanumModel(MecanumOptions options);

  std::string name() const override { return "mecanum"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static MecanumModel fromYaml(const std::string& text);

  /// (r_FL, r_FR, r_RL, r_RR, lx + ly) [m].
  const Eigen::Matrix<double, 5, 1>& intrinsics() const { return state_.intrinsics; }
  const Pose2& T_base_sensor() const { return state_.T_base_sensor; }
  /// Covariance of (r_FL, r_FR, r_RL, r_RR, lx + ly, x, y, theta); zero until a fit succeeds.
  const Eigen::Matrix<double, 8, 8>& covariance() const { return state_.covariance; }

private:
  MecanumOptions options_;
  SensorMotionState<kMecanumParameterCount> state_;
};

}  // namespace odometry_calibration
