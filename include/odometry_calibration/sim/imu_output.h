// The simulator's IMU output (scenario `imu:`): the gyro's readings (imu_model.h) at the IMU's
// rate, from the start on, while the IMU is enabled.
#pragma once

#include <cstdint>

#include "odometry_calibration/sim/imu_model.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {

class ImuOutput
{
public:
  /// The IMU of `options`, on the random stream of `seed` (its own).
  ImuOutput(const ImuOptions& options, unsigned seed);

  /// When the next reading is due [ns of true time]; never when the IMU is disabled.
  std::int64_t next() const { return next_ns_; }

  /// At true time `now_ns` [ns] (`t_s` [s]) with the base's true yaw rate `yaw_rate_rad_s`
  /// [rad/s]: the reading due now, if any, to `sink`.
  void publishDue(std::int64_t now_ns, double t_s, double yaw_rate_rad_s, SimulationSink& sink);

private:
  ImuModel model_;
  std::int64_t period_ns_;
  std::int64_t next_ns_;
};

}  // namespace sim
}  // namespace odometry_calibration
