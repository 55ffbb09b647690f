#include "odometry_calibration/session/gyro_health.h"

#include "odometry_calibration/common/number_text.h"

namespace odometry_calibration {

GyroHealth::GyroHealth(SessionLog log) : log_(std::move(log)) {}

void GyroHealth::watch(const GyroFit& fit)
{
  std::lock_guard<std::mutex> lock(mutex_);
  alarm_told_ = false;
  monitor_.reset();
  if (!fit.fitted)
    return;
  monitor_ = std::make_unique<GyroHealthMonitor>(
      GyroCalibration{fit.scale.value, fit.bias.value, fit.shift_s}, GyroHealthOptions{});
}

void GyroHealth::addReading(double stamp_s, double yaw_rate_rad_s)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!monitor_)
    return;
  monitor_->addReading(stamp_s, yaw_rate_rad_s);  // GyroSource has refused the bad ones
  sayAlarm();
}

void GyroHealth::addPair(const MotionPair& pair)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!monitor_)
    return;
  monitor_->addPair(pair);
  sayAlarm();
}

void GyroHealth::sayAlarm()
{
  if (alarm_told_ || !monitor_->status().alarm)
    return;
  alarm_told_ = true;
  if (log_)
    log_(SessionLogLevel::kWarn, "gyro health: " + monitor_->status().message);
}

std::optional<SessionStatusReport> GyroHealth::status() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!monitor_)
    return std::nullopt;
  const GyroHealthStatus health = monitor_->status();
  SessionStatusReport report;
  report.name = "gyro health";
  report.level = health.alarm ? SessionStatusReport::Level::kWarn : SessionStatusReport::Level::kOk;
  report.message = health.message;
  report.add("statistic (alarm at 1)", formatNumber(health.statistic, 4));
  report.add("CUSUM threshold h [sigma]", formatNumber(health.threshold, 4));
  report.add("pairs scored", std::to_string(health.pairs));
  report.add("pairs skipped", std::to_string(health.skipped));
  for (const GyroHealthChart& chart : health.charts) {
    report.add(chart.name + " CUSUM (U, L) [sigma]",
               chart.calibrated ? formatNumber(chart.upper, 3) + ", " + formatNumber(chart.lower, 3)
                                : "learning its noise (" + std::to_string(chart.count) + " pairs)");
  }
  return report;
}

void GyroHealth::clear()
{
  std::lock_guard<std::mutex> lock(mutex_);
  monitor_.reset();
  alarm_told_ = false;
}

}  // namespace odometry_calibration
