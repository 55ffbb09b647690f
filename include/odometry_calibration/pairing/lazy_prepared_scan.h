// A scan whose preparation for matching (points, local lines: prepareScan) runs once, in the
// first thread that needs it: the reading thread hands scans on without preparing them, and
// whichever thread matches a scan first prepares it (match_queue.h).
#pragma once

#include <mutex>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// A scan, prepared on first use. Thread-safe.
class LazyPreparedScan
{
public:
  /// Checks the scan's geometry and the options now (throws std::invalid_argument like
  /// prepareScan), so that a bad scan is reported by the call that brought it.
  LazyPreparedScan(Scan scan, const LineFitOptions& options);
  LazyPreparedScan(const LazyPreparedScan&) = delete;
  LazyPreparedScan& operator=(const LazyPreparedScan&) = delete;

  /// Whether the scan has per-ray times (time_increment_s or ray_times_s), so that its sweep
  /// can be compensated with setSweepVelocity.
  bool hasRayTimes() const { return has_ray_times_; }

  /// The scan's sweep duration (sweepDuration, scan.h) [s].
  double sweepDuration() const { return sweep_duration_s_; }

  /// The sensor's velocity during the sweep, used by the preparation (motion compensation,
  /// scan.h). Call before the first get().
  void setSweepVelocity(const SensorVelocity& velocity) { velocity_ = velocity; }
  const SensorVelocity& sweepVelocity() const { return velocity_; }

  /// The prepared scan (prepared by the first caller; the others wait for it).
  const PreparedScan& get() const;

private:
  mutable std::once_flag once_;
  mutable Scan scan_;  ///< released once prepared
  bool has_ray_times_ = false;
  double sweep_duration_s_ = 0.0;
  LineFitOptions options_;
  SensorVelocity velocity_;
  mutable PreparedScan prepared_;
};

}  // namespace odometry_calibration
