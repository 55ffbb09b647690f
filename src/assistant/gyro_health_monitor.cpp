#include "odometry_calibration/assistant/gyro_health_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/Dense>

#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/common/median.h"

namespace odometry_calibration {
namespace {

constexpr std::size_t kScaleChart = 0;
constexpr std::size_t kBiasChart = 1;

/// The spread of `values`: the root mean square deviation from their median of those within
/// 4 robust sigmas (1.4826 MAD) of it, so that an outlier does not inflate it while the estimate
/// keeps nearly the standard deviation's efficiency (the MAD's is 37 % of it: a spread a third
/// too small on 50 values is not rare, and a chart so scaled raises false alarms).
double robustSpread(const std::vector<double>& values)
{
  const double centre = median(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (const double value : values)
    deviations.push_back(std::abs(value - centre));
  const double limit = 4.0 * 1.4826 * median(deviations);
  double sum = 0.0;
  std::size_t count = 0;
  for (const double deviation : deviations) {
    if (deviation <= limit) {
      sum += deviation * deviation;
      ++count;
    }
  }
  return count > 1 ? std::sqrt(sum / static_cast<double>(count - 1)) : 0.0;
}

}  // namespace

void validate(const GyroHealthOptions& options)
{
  if (!(options.false_alarm_pairs >= 10.0) || !std::isfinite(options.false_alarm_pairs))
    throw std::invalid_argument("gyro health monitor: false_alarm_pairs must be >= 10");
  if (!(options.design_shift_sigma > 0.0) || options.design_shift_sigma > 10.0)
    throw std::invalid_argument("gyro health monitor: design_shift_sigma must be in (0, 10]");
  if (options.burn_in_pairs < 10)
    throw std::invalid_argument("gyro health monitor: burn_in_pairs must be >= 10");
  if (options.chart_burn_in_pairs < 5)
    throw std::invalid_argument("gyro health monitor: chart_burn_in_pairs must be >= 5");
  if (!(options.clip_sigma > options.design_shift_sigma) || !std::isfinite(options.clip_sigma))
    throw std::invalid_argument("gyro health monitor: clip_sigma must exceed design_shift_sigma");
  if (!(options.min_rotation_rad > 0.0) || !std::isfinite(options.min_rotation_rad))
    throw std::invalid_argument("gyro health monitor: min_rotation_rad must be > 0");
  if (!(options.max_gap_s > 0.0) || !(options.history_s > options.max_gap_s) ||
      !std::isfinite(options.history_s))
    throw std::invalid_argument(
        "gyro health monitor: max_gap_s must be > 0 and history_s finite and above it");
  if (options.max_pending_pairs < 1)
    throw std::invalid_argument("gyro health monitor: max_pending_pairs must be >= 1");
}

GyroHealthMonitor::GyroHealthMonitor(const GyroCalibration& calibration, GyroHealthOptions options)
    : calibration_(calibration), options_(options)
{
  if (!std::isfinite(calibration.scale) || !(calibration.scale > 0.0))
    throw std::invalid_argument("gyro health monitor: the gyro's scale must be finite and > 0");
  if (!std::isfinite(calibration.bias_rad_s) || !std::isfinite(calibration.shift_s))
    throw std::invalid_argument("gyro health monitor: the gyro's bias and shift must be finite");
  validate(options_);
  k_ = 0.5 * options_.design_shift_sigma;
  // Two charts, two sides each share the false alarms.
  h_ = cusumThreshold(k_, 4.0 * options_.false_alarm_pairs);
  charts_[kScaleChart].name = "gyro scale";
  charts_[kBiasChart].name = "gyro bias";
}

std::string GyroHealthMonitor::addReading(double stamp_s, double yaw_rate_rad_s)
{
  if (!std::isfinite(stamp_s) || !std::isfinite(yaw_rate_rad_s))
    return "gyro reading with a stamp or rate that is not finite";
  Reading reading{stamp_s, yaw_rate_rad_s, 0.0, false};
  if (!readings_.empty()) {
    const Reading& last = readings_.back();
    if (!(stamp_s > last.stamp_s))
      return "gyro reading stamped " + std::to_string(stamp_s) + " s, not after the last (" +
             std::to_string(last.stamp_s) + " s)";
    const double dt = stamp_s - last.stamp_s;
    reading.heading_rad = last.heading_rad + 0.5 * (last.rate_rad_s + yaw_rate_rad_s) * dt;
    reading.after_gap = dt > options_.max_gap_s;
  }
  readings_.push_back(reading);
  while (readings_.front().stamp_s < stamp_s - options_.history_s)
    readings_.pop_front();
  scorePending();
  return "";
}

bool GyroHealthMonitor::addPair(const MotionPair& pair)
{
  pending_.push_back(pair);
  while (pending_.size() > options_.max_pending_pairs) {
    pending_.pop_front();
    ++skipped_;
  }
  return scorePending();
}

bool GyroHealthMonitor::scorePending()
{
  bool raised = false;
  while (!pending_.empty() && !readings_.empty()) {
    const MotionPair& pair = pending_.front();
    if (readings_.back().stamp_s < pair.end_stamp_s + calibration_.shift_s)
      break;  // the readings do not cover it yet (pairs come in time order)
    raised = score(pair) || raised;
    pending_.pop_front();
  }
  return raised;
}

bool GyroHealthMonitor::covered(double start_s, double end_s) const
{
  if (readings_.empty() || start_s < readings_.front().stamp_s || end_s > readings_.back().stamp_s)
    return false;
  const auto first = std::upper_bound(
      readings_.begin(), readings_.end(), start_s,
      [](double stamp, const Reading& reading) { return stamp < reading.stamp_s; });
  for (auto it = first; it != readings_.end(); ++it) {
    if (it->after_gap)
      return false;
    if (it->stamp_s >= end_s)
      break;
  }
  return true;
}

bool GyroHealthMonitor::headingAt(double stamp_s, double* heading_rad) const
{
  const auto after = std::lower_bound(
      readings_.begin(), readings_.end(), stamp_s,
      [](const Reading& reading, double stamp) { return reading.stamp_s < stamp; });
  if (after == readings_.end())
    return false;
  if (after->stamp_s == stamp_s || after == readings_.begin()) {
    *heading_rad = after->heading_rad;
    return after->stamp_s == stamp_s;
  }
  // Trapezoid from the reading before to stamp_s, the rate interpolated linearly.
  const Reading& before = *(after - 1);
  const double fraction = (stamp_s - before.stamp_s) / (after->stamp_s - before.stamp_s);
  const double rate = before.rate_rad_s + fraction * (after->rate_rad_s - before.rate_rad_s);
  *heading_rad = before.heading_rad + 0.5 * (before.rate_rad_s + rate) * (stamp_s - before.stamp_s);
  return true;
}

bool GyroHealthMonitor::score(const MotionPair& pair)
{
  const double start_s = pair.start_stamp_s + calibration_.shift_s;
  const double end_s = pair.end_stamp_s + calibration_.shift_s;
  const double duration_s = pair.end_stamp_s - pair.start_stamp_s;
  const double dtheta = pair.sensor_motion.theta();
  double g0 = 0.0, g1 = 0.0;
  if (!(duration_s > 0.0) || !std::isfinite(dtheta) || !covered(start_s, end_s) ||
      !headingAt(start_s, &g0) || !headingAt(end_s, &g1)) {
    ++skipped_;
    return false;
  }
  const double gyro_rad = g1 - g0;
  scored_.push_back({gyro_rad, dtheta, duration_s});
  const double residual =
      (gyro_rad - calibration_.bias_rad_s * duration_s) / calibration_.scale - dtheta;
  if (std::abs(dtheta) > options_.min_rotation_rad)
    return feed(charts_[kScaleChart], residual * dtheta, pair.end_stamp_s);
  return feed(charts_[kBiasChart], residual / duration_s, pair.end_stamp_s);
}

bool GyroHealthMonitor::feed(GyroHealthChart& chart, double value, double stamp_s)
{
  ++chart.count;
  if (!chart.calibrated) {
    chart.burn_in.push_back(value);
    if (chart.burn_in.size() < static_cast<std::size_t>(options_.burn_in_pairs))
      return false;
    chart.spread = std::max(robustSpread(chart.burn_in), 1e-12);
    chart.calibrated = true;
    chart.burn_in.clear();
    chart.upper_zero_at = chart.lower_zero_at = scored_.size();
    return false;
  }
  const double clip = options_.clip_sigma;
  const double raw = std::clamp(value / chart.spread, -clip, clip);
  const double n = static_cast<double>(chart.centre_count);
  const double n0 = options_.chart_burn_in_pairs;
  const double centre = chart.centre_sum / (n + n0);
  const double z =
      std::clamp((raw - centre) / std::sqrt(1.0 + n / ((n + n0) * (n + n0))), -clip, clip);
  if (!alarm_) {
    chart.centre_sum += raw;
    ++chart.centre_count;
  }
  chart.upper = std::max(0.0, chart.upper + z - k_);
  chart.lower = std::max(0.0, chart.lower - z - k_);
  if (chart.upper == 0.0)
    chart.upper_zero_at = scored_.size();
  if (chart.lower == 0.0)
    chart.lower_zero_at = scored_.size();
  if (alarm_ || std::max(chart.upper, chart.lower) <= h_)
    return false;
  alarm_ = true;
  alarm_chart_ = static_cast<std::size_t>(&chart - charts_.data());
  change_at_ = chart.upper > h_ ? chart.upper_zero_at : chart.lower_zero_at;
  alarm_stamp_s_ = stamp_s;
  return true;
}

void GyroHealthMonitor::fitSinceChange(GyroHealthStatus* status) const
{
  // Least squares of gyro = s' dtheta + b' duration over the pairs since the change point.
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d right = Eigen::Vector2d::Zero();
  for (std::size_t i = change_at_; i < scored_.size(); ++i) {
    const Eigen::Vector2d row(scored_[i].dtheta_rad, scored_[i].duration_s);
    normal += row * row.transpose();
    right += row * scored_[i].gyro_rad;
  }
  status->pairs_since_change = scored_.size() - std::min(change_at_, scored_.size());
  const Eigen::LDLT<Eigen::Matrix2d> solver(normal);
  const Eigen::Vector2d solution = solver.solve(right);
  status->scale_now = calibration_.scale;
  status->bias_now_rad_s = calibration_.bias_rad_s;
  status->cause = status->alarm_chart;
  if (status->pairs_since_change < 3 || solver.info() != Eigen::Success || !solution.allFinite())
    return;
  status->scale_now = solution(0);
  status->bias_now_rad_s = solution(1);
  // Which changed: the larger change in units of its σ (covariance sigma^2 N^-1, sigma^2 the
  // residuals' variance with 2 unknowns).
  double squares = 0.0;
  for (std::size_t i = change_at_; i < scored_.size(); ++i) {
    const double fitted = solution(0) * scored_[i].dtheta_rad + solution(1) * scored_[i].duration_s;
    squares += std::pow(scored_[i].gyro_rad - fitted, 2);
  }
  const Eigen::Matrix2d covariance = squares / static_cast<double>(status->pairs_since_change - 2) *
                                     solver.solve(Eigen::Matrix2d::Identity());
  const double scale_t = std::abs(solution(0) - calibration_.scale) / std::sqrt(covariance(0, 0));
  const double bias_t =
      std::abs(solution(1) - calibration_.bias_rad_s) / std::sqrt(covariance(1, 1));
  if (std::isfinite(scale_t) && std::isfinite(bias_t))
    status->cause = scale_t >= bias_t ? "gyro scale" : "gyro bias";
}

GyroHealthStatus GyroHealthMonitor::status() const
{
  GyroHealthStatus status;
  status.alarm = alarm_;
  status.pairs = scored_.size();
  status.skipped = skipped_;
  status.threshold = h_;
  status.charts = charts_;
  for (const GyroHealthChart& chart : charts_)
    status.statistic = std::max(status.statistic, std::max(chart.upper, chart.lower) / h_);
  if (!alarm_) {
    status.message = "ok";
    return status;
  }
  status.alarm_chart = charts_[alarm_chart_].name;
  status.alarm_stamp_s = alarm_stamp_s_;
  fitSinceChange(&status);
  char text[320];
  std::snprintf(
      text, sizeof(text),
      "%s drifted (%s chart alarm at %.1f s): over the %zu pairs since the change the gyro reads "
      "scale %.4f (calibrated %.4f, %+.2f %%) and bias %.5f rad/s (calibrated %.5f); "
      "refit (call ~calibrate)",
      status.cause.c_str(), status.alarm_chart.c_str(), alarm_stamp_s_, status.pairs_since_change,
      status.scale_now, calibration_.scale, 100.0 * (status.scale_now / calibration_.scale - 1.0),
      status.bias_now_rad_s, calibration_.bias_rad_s);
  status.message = text;
  return status;
}

}  // namespace odometry_calibration
