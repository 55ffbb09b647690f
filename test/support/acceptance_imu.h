// The simulated IMU of the gyro's acceptance: a gyro 1.5 % high, a 0.01 rad/s bias walking
// 1e-6 rad/s/sqrt(s), 2 mrad/s of noise, its clock 20 ms late; and its readings made the
// base's yaw rate.
#pragma once

#include <vector>

#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/sim/imu_model.h"

namespace odometry_calibration::test {

inline sim::ImuOptions acceptanceImu()
{
  sim::ImuOptions imu;
  imu.enabled = true;
  imu.scale = 1.015;
  imu.bias_rad_s = 0.01;
  imu.bias_random_walk = 1e-6;
  imu.noise_rad_s = 0.002;
  imu.time_offset_s = 0.02;
  return imu;
}

/// The base's yaw rate of each reading of an IMU mounted with `roll`, `pitch` [rad].
inline std::vector<GyroSample> yawRates(const std::vector<sim::ImuSample>& imu, double roll,
                                        double pitch)
{
  std::vector<GyroSample> samples;
  for (const sim::ImuSample& s : imu)
    samples.push_back({s.stamp_s, gyroYawRate(s.angular_velocity, roll, pitch)});
  return samples;
}

}  // namespace odometry_calibration::test
