// Dead reckoning through a calibration model: the odometry the live node publishes.
//
// A model predicts the sensor's displacement s over a window of encoder samples (paper eq. 1:
// s = f(delta)); it was trained on windows of one keyframe interval, so the integrator chains
// windows of at most `segment_s`: the pose since the last anchor is anchor ⊕ f(samples since
// the anchor) (paper Table I's ⊕), and a new anchor is set once the window spans segment_s.
// The covariance is propagated to first order through each ⊕:
//   Σ_new = J_a Σ_anchor J_aᵀ + J_d Σ_f J_dᵀ,
//   J_a = [1 0 -(s x_d + c y_d); 0 1 (c x_d - s y_d); 0 0 1], J_d = R(θ_anchor) (3×3 block).
// With a known extrinsic T_base_sensor the tracked frame is base_link (odom's origin is where
// base_link starts): T_odom_base = T_odom_sensor ⊕ T_base_sensor⁻¹. Without one (model-free
// models) the tracked frame is the sensor itself.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

class OdometryIntegrator
{
public:
  /// @param model predicts the sensor's motion (shared: the node swaps models after a fit)
  /// @param T_base_sensor the sensor's pose in base_link, if known
  /// @param segment_s longest window given to the model [s] (the keyframe interval); > 0
  OdometryIntegrator(std::shared_ptr<const MotionModel> model, std::optional<Pose2> T_base_sensor,
                     double segment_s);

  /// Adds a decoded encoder sample. Samples not later than the last one are ignored (returns
  /// false). Throws what the model's predict throws (the state is then unchanged).
  bool add(const EncoderSample& sample);

  /// Added to every window's predicted covariance: the uncertainty a model does not report
  /// itself (e.g. the nominal robot before any fit, whose prediction covariance is zero).
  void setWindowCovarianceFloor(const Eigen::Matrix3d& floor) { covariance_floor_ = floor; }

  /// Back to the origin with no history.
  void reset();

  /// Continues from `T_odom_tracked` (the tracked frame's pose) with zero covariance, from the
  /// last sample: used when a new model takes over, so the odometry does not jump.
  void restartAt(const Pose2& T_odom_tracked);

  /// Whether the tracked frame is base_link (extrinsic known) or the sensor.
  bool tracksBase() const { return T_base_sensor_.has_value(); }
  /// Pose of the tracked frame in odom [m, m, rad] and its covariance [m^2, rad^2].
  Pose2 pose() const;
  Eigen::Matrix3d covariance() const;
  /// Pose of the sensor in odom.
  const Pose2& sensorPose() const { return T_odom_sensor_; }
  /// Velocity of the tracked frame in its own axes over the last update (vx [m/s], vy [m/s],
  /// omega [rad/s]); zero before two samples.
  const Eigen::Vector3d& velocity() const { return velocity_; }
  /// The last sample added (null before the first).
  const EncoderSample* lastSample() const { return window_.empty() ? nullptr : &window_.back(); }
  /// Covariance of the last window's predicted motion (floor included), in the sensor's frame
  /// [m^2, rad^2]: how uncertain one keyframe interval's motion is.
  const Eigen::Matrix3d& windowCovariance() const { return window_covariance_; }
  /// Time of the last sample [s]; NaN before the first.
  double stamp() const;
  /// The longest window given to the model [s] (the constructor's segment_s).
  double segmentLength() const { return segment_s_; }

private:
  std::shared_ptr<const MotionModel> model_;
  std::optional<Pose2> T_base_sensor_;
  double segment_s_;
  Eigen::Matrix3d covariance_floor_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d window_covariance_ = Eigen::Matrix3d::Zero();
  Pose2 T_odom_sensor_anchor_;
  Eigen::Matrix3d covariance_anchor_ = Eigen::Matrix3d::Zero();
  std::vector<EncoderSample> window_;  ///< samples since the anchor, the anchor's first
  Pose2 T_odom_sensor_;
  Eigen::Matrix3d covariance_sensor_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace odometry_calibration
