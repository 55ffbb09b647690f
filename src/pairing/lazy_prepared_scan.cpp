#include "odometry_calibration/pairing/lazy_prepared_scan.h"

#include <utility>

namespace odometry_calibration {

LazyPreparedScan::LazyPreparedScan(Scan scan, const LineFitOptions& options)
    : scan_(std::move(scan)), options_(options)
{
  validate(scan_);
  validate(options_);
  has_ray_times_ = odometry_calibration::hasRayTimes(scan_);
  sweep_duration_s_ = odometry_calibration::sweepDuration(scan_);
}

const PreparedScan& LazyPreparedScan::get() const
{
  std::call_once(once_, [this] {
    prepared_ = prepareScan(scan_, options_, velocity_);
    scan_ = Scan();
  });
  return prepared_;
}

}  // namespace odometry_calibration
