// A base that publishes only its own odometry (nav_msgs/Odometry, wheels.source odometry): its
// pose increments in base_link are the input, and the model corrects them by a translation
// scale and a rotation scale and finds the sensor's pose in base_link.
//
// The base's odometry reaches the models as three cumulative "joints" (session/wheel_signals.h):
// the forward and lateral path [m] and the heading [rad], summed message by message in the base
// frame at the previous message, so that between consecutive samples the increments
// (ds, dl, dtheta) are the base's own motion T_{k-1}^-1 T_k = (ds, dl, dtheta). The corrected
// base motion of a step is (k_t ds, k_t dl, k_r dtheta), composed over the samples; the sensor
// motion is T_bs^-1 * Delta_base * T_bs (parametric_model.h).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/data/pair_features.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/encoder_steps.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/sensor_motion_state.h"

namespace odometry_calibration {

/// The three joints a base odometry becomes, in this order: forward path [m], lateral path [m],
/// heading [rad].
const std::vector<std::string>& baseOdometryJointNames();

/// Where the base odometry's cumulative path and heading are in an EncoderSample.
struct BaseOdometryLayout
{
  int forward_index = 0;  ///< forward path [m]
  int lateral_index = 1;  ///< lateral path [m]
  int yaw_index = 2;      ///< heading [rad]
};

/// Indices into the 2-vector of intrinsic parameters.
enum BaseOdometryParameterIndex
{
  kTranslationScale = 0,       ///< k_t: true translation per reported one [-]
  kRotationScale = 1,          ///< k_r: true rotation per reported one [-]
  kBaseOdometryParameterCount  ///< 2
};

/// The base odometry's scales as a kinematic model for fitSensorMotion: each step between
/// consecutive samples is the reported increment with its translation times k_t and its
/// rotation times k_r, Delta_k = (k_t ds, k_t dl, k_r dtheta).
struct BaseOdometryKinematics
{
  using Layout = BaseOdometryLayout;
  static constexpr int kIntrinsics = kBaseOdometryParameterCount;
  template <typename T>
  static Pose2T<T> integrate(const T* intrinsic, const Layout& layout,
                             const std::vector<EncoderSample>& samples)
  {
    return composeEncoderSteps<T>(samples, [&](const EncoderSample& previous,
                                               const EncoderSample& current) {
      const auto step = [&](int index) { return current.values(index) - previous.values(index); };
      return Pose2T<T>(intrinsic[kTranslationScale] * T(step(layout.forward_index)),
                       intrinsic[kTranslationScale] * T(step(layout.lateral_index)),
                       intrinsic[kRotationScale] * T(step(layout.yaw_index)));
    });
  }
};

/// Options of the base odometry model.
struct BaseOdometryOptions
{
  BaseOdometryLayout layout;
  double initial_translation_scale = 1.0;  ///< start value of k_t [-]
  double initial_rotation_scale = 1.0;     ///< start value of k_r [-]
  Pose2 initial_T_base_sensor;             ///< start value of the sensor pose
  double huber_threshold = 3.0;            ///< Huber threshold on a pair's whitened error [sigma]
  int max_iterations = 500;                ///< Levenberg-Marquardt iteration cap (per solve)
  int yaw_starts = 8;                      ///< global starts of the sensor yaw
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const BaseOdometryOptions& options);

/// The base odometry's joints among `joints` (by baseOdometryJointNames()). Throws
/// std::invalid_argument naming the missing joint.
BaseOdometryLayout baseOdometryLayoutForJoints(const JointLayout& joints);

/// The fitted model: the scales (k_t, k_r), the sensor's pose and their 5x5 covariance.
class BaseOdometryModel : public MotionModel
{
public:
  explicit BaseOdometryModel(BaseOdometryOptions options);

  std::string name() const override { return "base_odometry"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static BaseOdometryModel fromYaml(const std::string& text);

  /// (k_t, k_r): the multipliers of the base's reported translation and rotation [-].
  const Eigen::Vector2d& scales() const { return state_.intrinsics; }
  const Pose2& T_base_sensor() const { return state_.T_base_sensor; }
  /// Covariance of (k_t, k_r, x, y, theta); zero until a fit succeeds.
  const Eigen::Matrix<double, 5, 5>& covariance() const { return state_.covariance; }

private:
  BaseOdometryOptions options_;
  SensorMotionState<kBaseOdometryParameterCount> state_;
};

}  // namespace odometry_calibration
