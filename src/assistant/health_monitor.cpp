#include "odometry_calibration/assistant/health_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/common/median.h"

namespace odometry_calibration {
namespace {

/// Siegmund's approximation of a one-sided CUSUM's in-control ARL (reference k, threshold h).
double siegmundArl0(double k, double h)
{
  const double b = h + 1.166;
  return (std::exp(2.0 * k * b) - 2.0 * k * b - 1.0) / (2.0 * k * k);
}

/// What a sustained shift of `signal` in direction `up` looks like, in words (the cause is the
/// attribution's).
std::string shiftWords(HealthSignal signal, bool up, const std::string& sensor)
{
  const std::string left_right = up ? "left" : "right";
  switch (signal) {
    case kTravelSignal:
      return up ? "travel reads long (the " + sensor + " sees more distance than the wheels report)"
                : "travel reads short (the " + sensor +
                      " sees less distance than the wheels report)";
    case kSidewaysSignal:
      return "the " + sensor + " sees sideways motion to the " + left_right + " while driving";
    case kRotationSignal:
      return up ? "rotation reads long (the " + sensor +
                      " sees more turning than the wheels report)"
                : "rotation reads short (the " + sensor +
                      " sees less turning than the wheels report)";
    case kHeadingDriftSignal:
      return "heading drifts to the " + left_right + " on straight runs";
    case kTurnSidewaysSignal:
      return "the " + sensor + " sees sideways motion " + (up ? "into" : "out of") +
             " each turn while turning";
    default:
      return "the " + sensor + " sees " + (up ? "forward" : "backward") +
             " motion on left turns and the reverse on right turns";
  }
}

/// The output (0 x, 1 y, 2 theta) each signal watches.
constexpr int kSignalOutput[kHealthSignalCount] = {0, 1, 2, 2, 1, 0};

}  // namespace

void validate(const HealthMonitorOptions& options)
{
  if (!(options.false_alarm_pairs >= 10.0) || !std::isfinite(options.false_alarm_pairs))
    throw std::invalid_argument("health monitor: false_alarm_pairs must be >= 10");
  if (!(options.design_shift_sigma > 0.0) || options.design_shift_sigma > 10.0)
    throw std::invalid_argument("health monitor: design_shift_sigma must be in (0, 10]");
  if (options.burn_in_pairs < 10)
    throw std::invalid_argument("health monitor: burn_in_pairs must be >= 10");
  if (options.chart_burn_in_pairs < 5)
    throw std::invalid_argument("health monitor: chart_burn_in_pairs must be >= 5");
  if (options.sensor_name.empty())
    throw std::invalid_argument("health monitor: sensor_name is empty");
  validate(options.attribution);
  if (!(options.clip_sigma > options.design_shift_sigma))
    throw std::invalid_argument("health monitor: clip_sigma must exceed design_shift_sigma");
  if (!(options.min_travel_m >= 0.0) || !(options.min_rotation_rad >= 0.0))
    throw std::invalid_argument("health monitor: min_travel_m and min_rotation_rad must be >= 0");
}

double cusumThreshold(double k, double arl0)
{
  if (!(k > 0.0) || !(arl0 > 1.0))
    throw std::invalid_argument("cusumThreshold: k must be > 0 and arl0 > 1");
  double low = 0.0, high = 1.0;
  while (siegmundArl0(k, high) < arl0) {
    high *= 2.0;
    if (high > 1e4)
      throw std::invalid_argument("cusumThreshold: arl0 out of reach");
  }
  for (int i = 0; i < 100; ++i) {
    const double middle = 0.5 * (low + high);
    (siegmundArl0(k, middle) < arl0 ? low : high) = middle;
  }
  return high;
}

HealthMonitor::HealthMonitor(std::shared_ptr<const MotionModel> model, HealthMonitorOptions options)
    : HealthMonitor(std::vector<WatchedSensor>{{std::move(model), options.sensor_name}}, options)
{
}

HealthMonitor::HealthMonitor(std::vector<WatchedSensor> sensors, HealthMonitorOptions options)
    : options_(std::move(options))
{
  if (sensors.empty())
    throw std::invalid_argument("health monitor: no sensor to watch");
  validate(options_);
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (!sensors[s].model)
      throw std::invalid_argument("health monitor: no model to watch");
    if (sensors[s].name.empty())
      throw std::invalid_argument("health monitor: sensor " + std::to_string(s) + " has no name");
    for (std::size_t t = 0; t < s; ++t) {
      if (sensors[t].name == sensors[s].name)
        throw std::invalid_argument("health monitor: two sensors are called '" + sensors[s].name +
                                    "'");
    }
  }
  k_ = 0.5 * options_.design_shift_sigma;
  // Two one-sided charts per signal and sensor share the false alarms (Bonferroni).
  h_ = cusumThreshold(k_, 2.0 * kHealthSignalCount * static_cast<double>(sensors.size()) *
                              options_.false_alarm_pairs);
  const char* names[] = {"travel",        "sideways",      "rotation",
                         "heading drift", "turn sideways", "turn along"};
  const char* outputs[] = {"x", "y", "theta"};
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    SensorState state;
    state.watched = std::move(sensors[s]);
    for (int c = 0; c < kHealthSignalCount; ++c) {
      HealthChart& chart = state.charts[static_cast<std::size_t>(c)];
      chart.name = names[c];
      chart.output = outputs[kSignalOutput[c]];
      chart.sensor = s;
      chart.sensor_name = state.watched.name;
    }
    sensors_.push_back(std::move(state));
  }
}

/// The attribution, on the first pair: the joints named by the options or "1", "2", ...
void HealthMonitor::makeAttribution(const MotionPair& pair)
{
  std::vector<std::string> joints = options_.joint_names;  // none given: "1", "2", ...
  for (Eigen::Index j = 0;
       options_.joint_names.empty() && j < pair.encoder_samples.front().values.size(); ++j)
    joints.push_back(std::to_string(j + 1));
  if (sensors_.size() == 1) {
    attribution_ = std::make_unique<ChangeAttribution>(
        makeChangeHypotheses(sensors_.front().watched.model, sensors_.front().watched.name, joints),
        options_.attribution);
    return;
  }
  std::vector<std::shared_ptr<const MotionModel>> models;
  std::vector<std::string> names;
  for (const SensorState& sensor : sensors_) {
    models.push_back(sensor.watched.model);
    names.push_back(sensor.watched.name);
  }
  attribution_ = std::make_unique<ChangeAttribution>(
      makeSensorsChangeHypotheses(models, names, joints), options_.attribution);
}

bool HealthMonitor::addPair(const MotionPair& pair, std::size_t sensor_index)
{
  if (sensor_index >= sensors_.size())
    throw std::invalid_argument("health monitor: a pair of sensor " + std::to_string(sensor_index) +
                                ", but " + std::to_string(sensors_.size()) +
                                " sensor(s) are watched");
  SensorState& sensor = sensors_[sensor_index];
  MotionPrediction prediction;
  try {
    prediction = sensor.watched.model->predict(pair.encoder_samples);
  } catch (const std::exception&) {
    ++skipped_;
    return false;
  }
  const Eigen::Matrix3d covariance = prediction.covariance + pair.covariance;
  const Pose2& p = prediction.mean;
  const Pose2& m = pair.sensor_motion;
  const Eigen::Vector3d residual(m.x() - p.x(), m.y() - p.y(),
                                 normalizeAngle(m.theta() - p.theta()));
  const Eigen::Vector3d sigma = covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!residual.allFinite() || !p.vector().allFinite() || !(sigma.minCoeff() > 0.0) ||
      !sigma.allFinite()) {
    ++skipped_;
    return false;
  }
  const Eigen::Vector3d z = residual.cwiseQuotient(sigma);
  ++pairs_;
  if (!attribution_)
    makeAttribution(pair);
  if (sensor.noise_learnt) {
    const Eigen::Matrix3d scale = sensor.output_scale.asDiagonal();
    attribution_->add(pairs_, pair.encoder_samples, residual, scale * covariance * scale,
                      sensor_index);
  }
  const bool was_alarm = alarm_;
  const bool travels = std::abs(p.x()) > options_.min_travel_m;
  const bool turns = std::abs(p.theta()) > options_.min_rotation_rad;
  if (travels || turns)
    learnNoise(sensor, z);
  const double direction = p.x() > 0.0 ? 1.0 : -1.0;
  const double turn = p.theta() > 0.0 ? 1.0 : -1.0;
  if (travels) {
    feed(sensor, kTravelSignal, direction * z(0), pair.end_stamp_s);
    feed(sensor, kSidewaysSignal, direction * z(1), pair.end_stamp_s);
    if (!turns)
      feed(sensor, kHeadingDriftSignal, direction * z(2), pair.end_stamp_s);
  }
  if (turns) {
    feed(sensor, kRotationSignal, turn * z(2), pair.end_stamp_s);
    feed(sensor, kTurnSidewaysSignal, turn * z(1), pair.end_stamp_s);
    feed(sensor, kTurnAlongSignal, turn * z(0), pair.end_stamp_s);
  }
  return alarm_ && !was_alarm;
}

/// Until burn_in_pairs pairs of `sensor` that move have come: their z per output, then its
/// robust spread.
void HealthMonitor::learnNoise(SensorState& sensor, const Eigen::Vector3d& z)
{
  if (sensor.noise_learnt)
    return;
  for (int k = 0; k < 3; ++k)
    sensor.noise_burn_in[static_cast<std::size_t>(k)].push_back(z(k));
  if (sensor.noise_burn_in[0].size() < static_cast<std::size_t>(options_.burn_in_pairs))
    return;
  for (int k = 0; k < 3; ++k) {
    std::vector<double>& values = sensor.noise_burn_in[static_cast<std::size_t>(k)];
    const double centre = median(values);
    std::vector<double> deviations;
    for (double v : values)
      deviations.push_back(std::abs(v - centre));
    sensor.output_scale(k) = std::max(1.4826 * median(deviations), 1e-6);
    values.clear();
    values.shrink_to_fit();
  }
  sensor.noise_learnt = true;
}

void HealthMonitor::feed(SensorState& sensor, HealthSignal signal, double value, double stamp_s)
{
  HealthChart& chart = sensor.charts[static_cast<std::size_t>(signal)];
  std::vector<double>& burn_in = sensor.burn_in[static_cast<std::size_t>(signal)];
  ++chart.count;
  const double clip = options_.clip_sigma;
  if (!chart.calibrated) {
    burn_in.push_back(value);
    if (!sensor.noise_learnt)
      return;
    // Ready with the noise: its output's spread (all moving pairs); the values so far start the
    // running centre.
    chart.scale = sensor.output_scale(kSignalOutput[signal]);
    for (double v : burn_in) {
      chart.centre_sum += std::clamp(v / chart.scale, -clip, clip);
      ++chart.centre_count;
    }
    chart.calibrated = true;
    chart.upper_zero_at = chart.lower_zero_at = pairs_;
    burn_in.clear();
    burn_in.shrink_to_fit();
    return;
  }
  // Self-starting centre (Hawkins 1987): the mean of the chart's earlier values, shrunk towards
  // 0 as if chart_burn_in_pairs more values had read 0 (a calibration fits its own robot without
  // bias); the difference's spread grows by its uncertainty, sqrt(1 + n / (n + n0)^2).
  const double n = static_cast<double>(chart.centre_count);
  const double n0 = options_.chart_burn_in_pairs;
  const double centre = chart.centre_sum / (n + n0);
  chart.centre = centre * chart.scale;
  const double standardised = std::clamp(value / chart.scale, -clip, clip);
  const double z =
      std::clamp((standardised - centre) / std::sqrt(1.0 + n / ((n + n0) * (n + n0))), -clip, clip);
  if (!alarm_) {
    chart.centre_sum += standardised;
    ++chart.centre_count;
  }
  chart.mean_recent += (z - chart.mean_recent) / 20.0;
  chart.upper = std::max(0.0, chart.upper + z - k_);
  chart.lower = std::max(0.0, chart.lower - z - k_);
  if (chart.upper == 0.0)
    chart.upper_zero_at = pairs_;
  if (chart.lower == 0.0)
    chart.lower_zero_at = pairs_;
  if (!alarm_ && (chart.upper > h_ || chart.lower > h_)) {
    alarm_ = true;
    alarm_output_ = chart.output;
    alarm_stamp_s_ = stamp_s;
    const bool up = chart.upper > h_;
    change_at_ = up ? chart.upper_zero_at : chart.lower_zero_at;
    alarm_sensor_ = chart.sensor;
    const std::string of_sensor = sensors_.size() > 1 ? " of " + sensor.watched.name : "";
    char where[160];
    std::snprintf(where, sizeof(where),
                  "output %s%s (%s chart, CUSUM %.1f > %.1f): ", chart.output.c_str(),
                  of_sensor.c_str(), chart.name.c_str(), std::max(chart.upper, chart.lower), h_);
    alarm_where_ = where + shiftWords(signal, up, sensor.watched.name);
  }
}

HealthStatus HealthMonitor::status() const
{
  HealthStatus status;
  status.active = true;
  status.alarm = alarm_;
  status.pairs = pairs_;
  status.threshold = h_;
  status.sensors = sensors_.size();
  for (const SensorState& sensor : sensors_)
    status.charts.insert(status.charts.end(), sensor.charts.begin(), sensor.charts.end());
  for (const HealthChart& chart : status.charts)
    status.statistic = std::max(status.statistic, std::max(chart.upper, chart.lower) / h_);
  status.alarm_output = alarm_output_;
  status.alarm_sensor = alarm_sensor_;
  status.alarm_stamp_s = alarm_stamp_s_;
  if (alarm_) {
    status.cause = attribution_->verdict(change_at_);
    status.message = alarm_where_ + "; " + status.cause.words +
                     "; the calibration no longer fits the robot: refit (call ~calibrate)";
  } else {
    const bool calibrated = std::any_of(status.charts.begin(), status.charts.end(),
                                        [](const HealthChart& c) { return c.calibrated; });
    char text[120];
    std::snprintf(text, sizeof(text), "ok: statistic %.2f of 1 (%zu pairs scored%s)",
                  status.statistic, pairs_, calibrated ? "" : ", still learning the noise");
    status.message = text;
  }
  return status;
}

}  // namespace odometry_calibration
