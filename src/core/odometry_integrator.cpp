#include "odometry_calibration/pipeline/odometry_integrator.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace odometry_calibration {

Eigen::Matrix3d composeCovariance(const Pose2& a, const Eigen::Matrix3d& covariance_a,
                                  const Pose2& d, const Eigen::Matrix3d& covariance_d)
{
  const double c = std::cos(a.theta()), s = std::sin(a.theta());
  Eigen::Matrix3d J_a = Eigen::Matrix3d::Identity();
  J_a(0, 2) = -s * d.x() - c * d.y();
  J_a(1, 2) = c * d.x() - s * d.y();
  Eigen::Matrix3d J_d = Eigen::Matrix3d::Identity();
  J_d.topLeftCorner<2, 2>() << c, -s, s, c;
  return J_a * covariance_a * J_a.transpose() + J_d * covariance_d * J_d.transpose();
}

Eigen::Vector3d se2Log(const Pose2& step)
{
  const double theta = step.theta();
  // V(theta) = [a -b; b a] with a = sin(theta)/theta, b = (1 - cos(theta))/theta; t = V v.
  const double a = std::abs(theta) < 1e-9 ? 1.0 : std::sin(theta) / theta;
  const double b = std::abs(theta) < 1e-9 ? 0.5 * theta : (1.0 - std::cos(theta)) / theta;
  const double det = a * a + b * b;
  return Eigen::Vector3d((a * step.x() + b * step.y()) / det, (-b * step.x() + a * step.y()) / det,
                         theta);
}

OdometryIntegrator::OdometryIntegrator(std::shared_ptr<const MotionModel> model,
                                       std::optional<Pose2> T_base_sensor, double segment_s)
    : model_(std::move(model)), T_base_sensor_(T_base_sensor), segment_s_(segment_s)
{
  if (!model_)
    throw std::invalid_argument("OdometryIntegrator: no model");
  if (!(segment_s_ > 0.0))
    throw std::invalid_argument("OdometryIntegrator: segment_s must be > 0");
  reset();
}

void OdometryIntegrator::reset()
{
  T_odom_sensor_anchor_ = T_base_sensor_ ? *T_base_sensor_ : Pose2();
  T_odom_sensor_ = T_odom_sensor_anchor_;
  covariance_anchor_.setZero();
  covariance_sensor_.setZero();
  velocity_.setZero();
  window_.clear();
}

void OdometryIntegrator::restartAt(const Pose2& T_odom_tracked)
{
  std::optional<EncoderSample> last;
  if (!window_.empty())
    last = window_.back();
  reset();
  T_odom_sensor_anchor_ = T_base_sensor_ ? T_odom_tracked * *T_base_sensor_ : T_odom_tracked;
  T_odom_sensor_ = T_odom_sensor_anchor_;
  if (last)
    window_.push_back(*last);  // the next sample's motion still counts
}

bool OdometryIntegrator::add(const EncoderSample& sample)
{
  if (!window_.empty() && !(sample.stamp_s > window_.back().stamp_s))
    return false;
  if (window_.empty()) {
    window_.push_back(sample);
    return true;
  }
  std::vector<EncoderSample> window = window_;
  window.push_back(sample);
  const MotionPrediction prediction = model_->predict(window);  // may throw: state unchanged
  const Pose2 previous = pose();
  const double dt = sample.stamp_s - window_.back().stamp_s;
  T_odom_sensor_ = T_odom_sensor_anchor_ * prediction.mean;
  window_covariance_ = prediction.covariance + covariance_floor_;
  covariance_sensor_ = composeCovariance(T_odom_sensor_anchor_, covariance_anchor_, prediction.mean,
                                         window_covariance_);
  velocity_ = se2Log(between(previous, pose())) / dt;
  if (sample.stamp_s - window.front().stamp_s >= segment_s_) {
    T_odom_sensor_anchor_ = T_odom_sensor_;
    covariance_anchor_ = covariance_sensor_;
    window_ = {sample};
  } else {
    window_ = std::move(window);
  }
  return true;
}

Pose2 OdometryIntegrator::pose() const
{
  return T_base_sensor_ ? T_odom_sensor_ * T_base_sensor_->inverse() : T_odom_sensor_;
}

Eigen::Matrix3d OdometryIntegrator::covariance() const
{
  if (!T_base_sensor_)
    return covariance_sensor_;
  // T_odom_base = T_odom_sensor ⊕ T_sensor_base with a fixed (known) T_sensor_base.
  return composeCovariance(T_odom_sensor_, covariance_sensor_, T_base_sensor_->inverse(),
                           Eigen::Matrix3d::Zero());
}

double OdometryIntegrator::stamp() const
{
  return window_.empty() ? std::numeric_limits<double>::quiet_NaN() : window_.back().stamp_s;
}

}  // namespace odometry_calibration
