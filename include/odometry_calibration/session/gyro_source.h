// The IMU's gyro in a calibration session: its readings (the base's yaw rate after the
// configured mounting, gyro_fit.h's gyroYawRate), the ones refused and why, and its fit against
// a source's pairs (fitGyro) when the session calibrates. Thread-safe: the node's subscription
// adds readings while a service call fits.
#pragma once

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/config/calibration_config.h"

namespace odometry_calibration {

class GyroSource
{
public:
  explicit GyroSource(const GyroConfig& config, double search_min_s, double search_max_s);

  /// One sensor_msgs/Imu reading at `stamp_s` [s]: `angular_velocity` [rad/s] in the IMU frame.
  /// Returns "" when kept, else why it was refused (a rate or stamp that is not finite or beyond
  /// 100 rad/s, a stamp not after the last kept one); refused readings are counted.
  std::string add(double stamp_s, const Eigen::Vector3d& angular_velocity);

  /// A reading that could not be used for `problem`: counted; returns `problem`.
  std::string refuse(const std::string& problem);

  /// The gyro's fit against `pairs` of a source whose time offset is `pairs_time_offset_s`.
  GyroFit fit(const std::vector<MotionPair>& pairs, double pairs_time_offset_s) const;

  std::size_t readings() const;
  std::size_t refused() const;
  /// The first refused reading's reason ("" when none was refused).
  std::string firstProblem() const;
  /// Drops every reading (the session's reset).
  void clear();

private:
  GyroConfig config_;
  GyroFitOptions options_;
  mutable std::mutex mutex_;
  std::vector<GyroSample> samples_;
  std::size_t refused_ = 0;
  std::string first_problem_;
};

}  // namespace odometry_calibration
