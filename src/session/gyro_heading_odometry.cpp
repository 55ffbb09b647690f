#include "odometry_calibration/session/gyro_heading_odometry.h"

#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/number_text.h"

namespace odometry_calibration {
namespace {

/// Readings kept before the newest [s]: a wheel state later than the gyro's by more finds none
/// and turns by the wheels.
constexpr double kKeptReadingsS = 2.0;

}  // namespace

GyroHeadingOdometry::GyroHeadingOdometry(double max_gap_s) : max_gap_s_(max_gap_s)
{
  if (!(max_gap_s > 0.0 && std::isfinite(max_gap_s)))
    throw std::invalid_argument("gyro heading odometry: gyro.max_gap_s must be > 0, got " +
                                formatNumber(max_gap_s));
}

std::string GyroHeadingOdometry::setCalibration(const GyroFit& fit)
{
  if (!fit.fitted)
    return "the gyro was not fitted (" + fit.problem + ")";
  if (!(std::isfinite(fit.scale.value) && fit.scale.value > 0.0))
    return "the gyro's scale " + formatNumber(fit.scale.value) + " is not a positive number";
  if (!std::isfinite(fit.bias.value) || !std::isfinite(fit.shift_s))
    return "the gyro's bias " + formatNumber(fit.bias.value) + " rad/s or clock shift " +
           formatNumber(fit.shift_s) + " s is not a number";
  std::lock_guard<std::mutex> lock(mutex_);
  fit_ = fit;
  last_wheels_.reset();  // the next state is the reference under the new fit
  return "";
}

bool GyroHeadingOdometry::calibrated() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return fit_.has_value();
}

std::string GyroHeadingOdometry::addReading(double stamp_s, double yaw_rate_rad_s)
{
  if (!std::isfinite(stamp_s) || !std::isfinite(yaw_rate_rad_s))
    return "gyro reading at " + formatNumber(stamp_s) + " s of " + formatNumber(yaw_rate_rad_s) +
           " rad/s is not a number";
  std::lock_guard<std::mutex> lock(mutex_);
  double integral = 0.0;
  if (!readings_.empty()) {
    const Reading& last = readings_.back();
    if (!(stamp_s > last.stamp_s))
      return "gyro reading at " + formatNumber(stamp_s) + " s not after the last at " +
             formatNumber(last.stamp_s) + " s";
    integral = last.integral + 0.5 * (last.rate_rad_s + yaw_rate_rad_s) * (stamp_s - last.stamp_s);
  }
  readings_.push_back({stamp_s, yaw_rate_rad_s, integral});
  dropReadingsBefore(stamp_s - kKeptReadingsS);
  return "";
}

std::optional<double> GyroHeadingOdometry::integralAt(double stamp_s) const
{
  if (readings_.empty() || stamp_s < readings_.front().stamp_s)
    return std::nullopt;
  const Reading& newest = readings_.back();
  if (stamp_s >= newest.stamp_s) {
    if (stamp_s - newest.stamp_s > max_gap_s_)
      return std::nullopt;
    return newest.integral + newest.rate_rad_s * (stamp_s - newest.stamp_s);
  }
  // The reading at or before stamp_s, then the trapezoid on the rate interpolated to stamp_s.
  std::size_t after = 1;
  while (readings_[after].stamp_s <= stamp_s)
    ++after;
  const Reading& a = readings_[after - 1];
  const Reading& b = readings_[after];
  if (b.stamp_s - a.stamp_s > max_gap_s_)
    return std::nullopt;
  const double h = stamp_s - a.stamp_s;
  if (h == 0.0)
    return a.integral;
  const double rate = a.rate_rad_s + (b.rate_rad_s - a.rate_rad_s) * h / (b.stamp_s - a.stamp_s);
  return a.integral + 0.5 * (a.rate_rad_s + rate) * h;
}

std::optional<double> GyroHeadingOdometry::rateAt(double stamp_s) const
{
  for (auto it = readings_.rbegin(); it != readings_.rend(); ++it) {
    if (it->stamp_s <= stamp_s)
      return (it->rate_rad_s - fit_->bias.value) / fit_->scale.value;
  }
  return std::nullopt;
}

bool GyroHeadingOdometry::gapBetween(double from_s, double to_s) const
{
  for (std::size_t k = 1; k < readings_.size() && readings_[k - 1].stamp_s < to_s; ++k) {
    if (readings_[k].stamp_s > from_s &&
        readings_[k].stamp_s - readings_[k - 1].stamp_s > max_gap_s_)
      return true;
  }
  return false;
}

void GyroHeadingOdometry::dropReadingsBefore(double stamp_s)
{
  while (readings_.size() > 1 && readings_[1].stamp_s <= stamp_s)
    readings_.pop_front();
}

void GyroHeadingOdometry::rebase(const OdometryState& wheels)
{
  if (at_wheels_) {  // the first state ever, after a reset or time going backwards
    pose_ = wheels.pose;
    heading_rad_ = wheels.pose.theta();
    at_wheels_ = false;
  }
  start_heading_rad_ = heading_rad_;
  start_stamp_s_ = wheels.stamp_s;
  last_wheels_ = wheels;
  last_integral_ = integralAt(wheels.stamp_s + fit_->shift_s);
}

OdometryState GyroHeadingOdometry::apply(const OdometryState& wheels)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!fit_)
    return wheels;
  if (last_wheels_ && !(wheels.stamp_s > last_wheels_->stamp_s)) {
    if (!(wheels.stamp_s < last_wheels_->stamp_s))
      return wheels;       // a repeated stamp
    last_wheels_.reset();  // time went backwards: start again at the wheels' pose
    at_wheels_ = true;
  }
  if (!last_wheels_ || wheels.continuity != last_wheels_->continuity ||
      wheels.tracks_base != last_wheels_->tracks_base) {
    rebase(wheels);
  } else {
    const double gyro_stamp_s = wheels.stamp_s + fit_->shift_s;
    const std::optional<double> integral = integralAt(gyro_stamp_s);
    const Pose2 step = last_wheels_->pose.inverse() * wheels.pose;
    const double dt = wheels.stamp_s - last_wheels_->stamp_s;
    double turn = step.theta();
    if (integral && last_integral_ && !gapBetween(gyro_stamp_s - dt, gyro_stamp_s)) {
      turn = (*integral - *last_integral_ - fit_->bias.value * dt) / fit_->scale.value;
      ++gyro_steps_;
    } else {
      ++wheel_steps_;
    }
    const double chord_rad = pose_.theta() + 0.5 * (turn - step.theta());
    const double c = std::cos(chord_rad), s = std::sin(chord_rad);
    heading_rad_ += turn;
    pose_ = Pose2(pose_.x() + c * step.x() - s * step.y(), pose_.y() + s * step.x() + c * step.y(),
                  normalizeAngle(heading_rad_));
    last_wheels_ = wheels;
    last_integral_ = integral;
  }
  OdometryState out = wheels;
  out.pose = pose_;
  if (const std::optional<double> rate = rateAt(wheels.stamp_s + fit_->shift_s))
    out.velocity(2) = *rate;
  const double turned = (heading_rad_ - start_heading_rad_) * fit_->scale.sigma / fit_->scale.value;
  const double drift = (wheels.stamp_s - start_stamp_s_) * fit_->bias.sigma / fit_->scale.value;
  out.covariance.row(2).setZero();
  out.covariance.col(2).setZero();
  out.covariance(2, 2) = turned * turned + drift * drift;
  return out;
}

std::size_t GyroHeadingOdometry::gyroSteps() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return gyro_steps_;
}

std::size_t GyroHeadingOdometry::wheelSteps() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return wheel_steps_;
}

void GyroHeadingOdometry::reset()
{
  std::lock_guard<std::mutex> lock(mutex_);
  readings_.clear();
  last_wheels_.reset();
  last_integral_.reset();
  at_wheels_ = true;
  gyro_steps_ = wheel_steps_ = 0;
}

}  // namespace odometry_calibration
