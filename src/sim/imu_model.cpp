#include "odometry_calibration/sim/imu_model.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace odometry_calibration {
namespace sim {

void validate(const ImuOptions& options)
{
  if (!options.enabled)
    return;
  auto require = [](bool ok, const std::string& what) {
    if (!ok)
      throw std::invalid_argument("imu." + what);
  };
  require(std::isfinite(options.rate_hz) && options.rate_hz > 0.0 && options.rate_hz <= 2000.0,
          "rate_hz must be in (0, 2000]");
  require(std::isfinite(options.scale) && options.scale > 0.5 && options.scale < 2.0,
          "scale must be in (0.5, 2)");
  require(std::isfinite(options.bias_rad_s) && std::abs(options.bias_rad_s) < 1.0,
          "bias_rad_s must be within 1 rad/s");
  require(std::isfinite(options.bias_random_walk) && options.bias_random_walk >= 0.0,
          "bias_random_walk must be >= 0");
  require(std::isfinite(options.noise_rad_s) && options.noise_rad_s >= 0.0,
          "noise_rad_s must be >= 0");
  require(std::isfinite(options.time_offset_s) && std::abs(options.time_offset_s) < 10.0,
          "time_offset_s must be within 10 s");
  require(std::isfinite(options.roll_rad) && std::abs(options.roll_rad) < M_PI / 2 &&
              std::isfinite(options.pitch_rad) && std::abs(options.pitch_rad) < M_PI / 2,
          "roll_rad and pitch_rad must be within pi/2");
  require(!options.topic.empty() && !options.frame_id.empty(),
          "topic and frame_id must not be empty");
}

Eigen::Matrix3d imuFromBase(const ImuOptions& options)
{
  const Eigen::Matrix3d R_base_imu =
      (Eigen::AngleAxisd(options.pitch_rad, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(options.roll_rad, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return R_base_imu.transpose();
}

ImuModel::ImuModel(const ImuOptions& options, unsigned seed)
    : options_(options),
      R_imu_base_(imuFromBase(options)),
      rng_(seed ^ 0x1a0c9f3ULL),
      bias_rad_s_(options.bias_rad_s)
{
}

ImuSample ImuModel::measure(double t_s, double yaw_rate_rad_s)
{
  const double dt_s = std::max(0.0, t_s - previous_t_s_);
  previous_t_s_ = t_s;
  bias_rad_s_ += options_.bias_random_walk * std::sqrt(dt_s) * unit_normal_(rng_);
  ImuSample sample;
  sample.stamp_s = t_s + options_.time_offset_s;
  sample.angular_velocity =
      options_.scale * (R_imu_base_ * Eigen::Vector3d(0.0, 0.0, yaw_rate_rad_s));
  sample.angular_velocity.z() += bias_rad_s_;
  for (int axis = 0; axis < 3; ++axis)
    sample.angular_velocity(axis) += options_.noise_rad_s * unit_normal_(rng_);
  return sample;
}

}  // namespace sim
}  // namespace odometry_calibration
