#include "odometry_calibration/sim/imu_output.h"

#include <cmath>
#include <limits>

namespace odometry_calibration {
namespace sim {

ImuOutput::ImuOutput(const ImuOptions& options, unsigned seed)
    : model_(options, seed),
      period_ns_(std::llround(1e9 / options.rate_hz)),
      next_ns_(options.enabled ? 0 : std::numeric_limits<std::int64_t>::max())
{
}

void ImuOutput::publishDue(std::int64_t now_ns, double t_s, double yaw_rate_rad_s,
                           SimulationSink& sink)
{
  if (now_ns != next_ns_)
    return;
  sink.onImu(model_.measure(t_s, yaw_rate_rad_s));
  next_ns_ += period_ns_;
}

}  // namespace sim
}  // namespace odometry_calibration
