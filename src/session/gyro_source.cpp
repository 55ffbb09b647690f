#include "odometry_calibration/session/gyro_source.h"

#include <cmath>
#include <cstdio>

namespace odometry_calibration {
namespace {

/// A yaw rate beyond this is no robot's (a corrupted message) [rad/s].
constexpr double kMaxRateRadS = 100.0;

}  // namespace

GyroSource::GyroSource(const GyroConfig& config, double search_min_s, double search_max_s)
    : config_(config)
{
  options_.search_min_s = search_min_s;
  options_.search_max_s = search_max_s;
  options_.max_gap_s = config.max_gap_s;
}

std::string GyroSource::add(double stamp_s, const Eigen::Vector3d& angular_velocity)
{
  std::lock_guard<std::mutex> lock(mutex_);
  char text[200];
  text[0] = '\0';
  const double rate = gyroYawRate(angular_velocity, config_.roll_rad, config_.pitch_rad);
  if (!std::isfinite(stamp_s)) {
    std::snprintf(text, sizeof(text), "gyro reading with a stamp that is not finite");
  } else if (!angular_velocity.allFinite() || !(std::abs(rate) <= kMaxRateRadS)) {
    std::snprintf(text, sizeof(text),
                  "gyro reading at %.3f s with angular velocity (%g, %g, %g) rad/s: not finite "
                  "or beyond %g rad/s",
                  stamp_s, angular_velocity.x(), angular_velocity.y(), angular_velocity.z(),
                  kMaxRateRadS);
  } else if (!samples_.empty() && !(stamp_s > samples_.back().stamp_s)) {
    std::snprintf(text, sizeof(text),
                  "gyro reading at %.6f s is not after the previous one (%.6f s): time going "
                  "backwards or a repeated stamp",
                  stamp_s, samples_.back().stamp_s);
  }
  if (text[0] != '\0') {
    if (refused_++ == 0)
      first_problem_ = text;
    return text;
  }
  samples_.push_back({stamp_s, rate});
  return "";
}

std::string GyroSource::refuse(const std::string& problem)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (refused_++ == 0)
    first_problem_ = problem;
  return problem;
}

GyroFit GyroSource::fit(const std::vector<MotionPair>& pairs, double pairs_time_offset_s) const
{
  std::vector<GyroSample> samples;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    samples = samples_;
  }
  return fitGyro(pairs, pairs_time_offset_s, samples, options_);
}

std::size_t GyroSource::readings() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return samples_.size();
}

std::size_t GyroSource::refused() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return refused_;
}

std::string GyroSource::firstProblem() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return first_problem_;
}

void GyroSource::clear()
{
  std::lock_guard<std::mutex> lock(mutex_);
  samples_.clear();
  refused_ = 0;
  first_problem_.clear();
}

}  // namespace odometry_calibration
