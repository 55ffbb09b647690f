// The live session's watch of its calibrated gyro: a GyroHealthMonitor (gyro_health_monitor.h)
// made from each ~calibrate's converged gyro fit, fed the gyro's readings and the first source's
// pairs, its alarm said once in the log and its state as the "gyro health" status. Thread-safe:
// the IMU subscription, the pairs and the service calls come from different threads.
#pragma once

#include <memory>
#include <mutex>
#include <optional>

#include "odometry_calibration/assistant/gyro_health_monitor.h"
#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/session/session_messages.h"

namespace odometry_calibration {

class GyroHealth
{
public:
  explicit GyroHealth(SessionLog log);
  /// Watches `fit` from now on (a fit that is not fitted stops the watch).
  void watch(const GyroFit& fit);
  /// One reading of the base's yaw rate [rad/s] at the gyro's stamp [s] (one kept by GyroSource).
  void addReading(double stamp_s, double yaw_rate_rad_s);
  /// One pair of the source the gyro was fitted against.
  void addPair(const MotionPair& pair);
  /// The "gyro health" status; none while no fit is watched.
  std::optional<SessionStatusReport> status() const;
  /// Stops watching (the session's reset).
  void clear();

private:
  void sayAlarm();

  SessionLog log_;
  mutable std::mutex mutex_;
  std::unique_ptr<GyroHealthMonitor> monitor_;
  bool alarm_told_ = false;
};

}  // namespace odometry_calibration
