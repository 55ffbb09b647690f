#include "odometry_calibration/calibration/odometry_integrator.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace odometry_calibration {

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
