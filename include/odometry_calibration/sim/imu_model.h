// The simulated IMU's gyro: the body's true yaw rate seen through a tilted mounting, a scale
// error, a bias that walks, white noise, stamped on the IMU's own clock. A reading at true time
// t is
//   w_imu = scale * R_imu_base * (0, 0, w_z(t)) + (0, 0, b(t)) + n,   n ~ N(0, noise^2 I),
//   b(t_k) = b(t_{k-1}) + bias_random_walk * sqrt(t_k - t_{k-1}) * N(0, 1),  b(0) = bias,
// stamped t + time_offset_s; R_imu_base turns base_link into the IMU's frame (roll about x, then
// pitch about y: R_base_imu = R_y(pitch) R_x(roll)).
#pragma once

#include <random>
#include <string>

#include <Eigen/Core>

namespace odometry_calibration {
namespace sim {

/// The scenario's `imu:` section. Off unless enabled.
struct ImuOptions
{
  bool enabled = false;
  double rate_hz = 100.0;             ///< readings per second [Hz]
  double scale = 1.0;                 ///< gyro scale factor [-] (1.015: reads 1.5 % high)
  double bias_rad_s = 0.0;            ///< bias at the start [rad/s]
  double bias_random_walk = 0.0;      ///< bias random walk [rad/s/sqrt(s)]
  double noise_rad_s = 0.0;           ///< white noise sigma per reading, each axis [rad/s]
  double time_offset_s = 0.0;         ///< stamp = true time + this (late clock: > 0) [s]
  double roll_rad = 0.0;              ///< mounting roll of the IMU in base_link [rad]
  double pitch_rad = 0.0;             ///< mounting pitch of the IMU in base_link [rad]
  std::string topic = "/imu/data";    ///< sensor_msgs/Imu in the bag
  std::string frame_id = "imu_link";  ///< header frame of the readings
};

/// One gyro reading on the IMU's clock.
struct ImuSample
{
  double stamp_s = 0.0;                                        ///< [s since start], IMU clock
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< in the IMU frame [rad/s]
};

/// Throws std::invalid_argument naming the first invalid field of `options` (only when enabled).
void validate(const ImuOptions& options);

/// The rotation of base_link into the IMU frame of `options`' roll and pitch (R_imu_base).
Eigen::Matrix3d imuFromBase(const ImuOptions& options);

/// Draws the readings of one IMU, on a random stream of its own.
class ImuModel
{
public:
  ImuModel(const ImuOptions& options, unsigned seed);
  /// The reading at true time `t_s` [s] for the base's true yaw rate `yaw_rate_rad_s`; the bias
  /// walks from the previous reading's time.
  ImuSample measure(double t_s, double yaw_rate_rad_s);

private:
  ImuOptions options_;
  Eigen::Matrix3d R_imu_base_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  double bias_rad_s_;
  double previous_t_s_ = 0.0;
};

}  // namespace sim
}  // namespace odometry_calibration
