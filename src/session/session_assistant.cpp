#include "odometry_calibration/session/session_assistant.h"

#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/common/number_text.h"

namespace odometry_calibration {
SessionAssistant::SessionAssistant(const SessionAssistantOptions& options,
                                   const CalibrationConfig& config, const std::string& config_text,
                                   const std::string& config_source, SessionLog log)
    : options_(options), log_(std::move(log))
{
  // The monitor names its candidate causes by the config's joints and ego-motion sensor.
  HealthMonitorOptions& health = options_.health_options;
  if (health.joint_names.empty()) {
    for (const JointConfig& joint : config.joints)
      health.joint_names.push_back(joint.name);
  }
  if (config.ego_motion == EgoMotionSource::kCloud)
    health.sensor_name = "lidar";
  else if (config.ego_motion != EgoMotionSource::kScan)
    health.sensor_name = "ego-motion sensor";
  // Several sources: each named by its frame, or its topic.
  for (const EgoMotionSourceConfig& source : config.ego_motion_sources)
    source_names_.push_back(source.frame.empty() ? source.topic : source.frame);
  if (!options_.guidance)
    return;
  // The fitted model's guidance, or the prior model's when the fitted one has none (gp).
  const std::string name = hasExcitationGuidance(config.model) ? config.model : config.prior_model;
  if (!hasExcitationGuidance(name)) {
    if (log_) {
      log_(SessionLogLevel::kInfo,
           "no excitation guidance: it needs a diff_drive, tricycle or mecanum model or "
           "prior_model");
    }
    return;
  }
  try {
    const CalibrationConfig for_model = configForModel(config_text, name, "", config_source);
    guidance_ = makeExcitationGuidance(name, for_model.models, options_.guidance_options);
    guidance_model_ = name;
    guidance_factory_ = for_model.models;
  } catch (const std::exception& error) {
    if (log_)
      log_(SessionLogLevel::kWarn, "no excitation guidance for " + name + ": " + error.what());
    guidance_.reset();
  }
}

void SessionAssistant::addPair(const MotionPair& pair, std::size_t source)
{
  if (guidance_ && source == 0)
    guidance_->addPair(pair);
  if (!health_monitor_ || source >= health_monitor_->sensors())
    return;
  const bool raised = health_monitor_->addPair(pair, source);
  if (!raised && (!health_monitor_->status().alarm || health_cause_told_))
    return;
  // The alarm, and once more when more pairs have told what changed (the cause is recomputed
  // from every pair since the change).
  const HealthStatus health = health_monitor_->status();
  const bool told = health.cause.quantity_told;
  if ((raised || told) && log_)
    log_(SessionLogLevel::kWarn, "calibration health: " + health.message);
  health_cause_told_ = told;
}

void SessionAssistant::watch(const std::shared_ptr<const MotionModel>& model,
                             const std::string& origin)
{
  if (!options_.health_monitor || !model)
    return;
  health_monitor_ = std::make_unique<HealthMonitor>(model, options_.health_options);
  health_model_origin_ = origin;
  health_cause_told_ = false;
}

void SessionAssistant::watch(const std::vector<std::shared_ptr<const MotionModel>>& models,
                             const std::string& origin)
{
  if (models.size() == 1) {
    watch(models.front(), origin);
    return;
  }
  if (models.size() != source_names_.size())
    throw std::invalid_argument("calibration health: " + std::to_string(models.size()) +
                                " models for " + std::to_string(source_names_.size()) +
                                " ego-motion sources");
  if (!options_.health_monitor)
    return;
  std::vector<WatchedSensor> sensors;
  for (std::size_t s = 0; s < models.size(); ++s)
    sensors.push_back({models[s], source_names_[s]});
  health_monitor_ = std::make_unique<HealthMonitor>(sensors, options_.health_options);
  health_model_origin_ = origin;
  health_cause_told_ = false;
}

void SessionAssistant::recentre(const std::string& model, const ModelReport& report,
                                const std::vector<MotionPair>& pairs)
{
  if (!guidance_ || model != guidance_model_)
    return;
  try {
    auto recentred = makeExcitationGuidance(model, guidance_factory_, options_.guidance_options,
                                            report.parameters);
    for (const MotionPair& pair : pairs)
      recentred->addPair(pair);
    guidance_ = std::move(recentred);
  } catch (const std::exception& error) {
    if (log_)
      log_(SessionLogLevel::kWarn,
           std::string("the guidance stays at its previous values: ") + error.what());
  }
}

void SessionAssistant::reset()
{
  if (guidance_)
    guidance_->reset();
}

std::string SessionAssistant::guidanceSummary() const
{
  return guidance_ ? " Guidance: " + guidance_->status().summary() + "." : std::string();
}

SessionStatusReport SessionAssistant::guidanceStatus() const
{
  const ExcitationStatus guidance = guidance_->status();
  SessionStatusReport status;
  status.name = "excitation guidance";
  status.message = guidance.summary();
  status.add("guidance model", guidance.model);
  status.add("ready to fit", guidance.ready_to_fit ? "true" : "false");
  for (std::size_t i = 0; i < guidance.missing_motions.size(); ++i)
    status.add("missing motion " + std::to_string(i + 1), guidance.missing_motions[i]);
  for (const ParameterGuidance& p : guidance.parameters) {
    status.add(p.name + " [" + p.unit + "]", (p.enough ? "enough: sigma " : "collecting: sigma ") +
                                                 formatNumber(p.sigma, 4) + " (target " +
                                                 formatNumber(p.target_sigma, 4) + ")");
  }
  return status;
}

SessionStatusReport SessionAssistant::healthStatus() const
{
  const HealthStatus health = health_monitor_->status();
  SessionStatusReport status;
  status.name = "calibration health";
  status.level = health.alarm ? SessionStatusReport::Level::kWarn : SessionStatusReport::Level::kOk;
  status.message = health.message;
  status.add("watching", health_model_origin_);
  status.add("statistic (alarm at 1)", formatNumber(health.statistic, 4));
  status.add("CUSUM threshold h [sigma]", formatNumber(health.threshold, 4));
  status.add("pairs scored", std::to_string(health.pairs));
  for (const HealthChart& chart : health.charts) {
    const std::string sensor = health.sensors > 1 ? chart.sensor_name + " " : "";
    status.add("chart " + sensor + chart.name + " (" + chart.output + ")",
               chart.calibrated
                   ? "U " + formatNumber(chart.upper, 4) + ", L " + formatNumber(chart.lower, 4) +
                         ", recent mean " + formatNumber(chart.mean_recent, 4) + " sigma"
                   : "learning the noise (" + std::to_string(chart.count) + " pairs)");
  }
  return status;
}

void SessionAssistant::addStatuses(std::vector<SessionStatusReport>* statuses) const
{
  if (guidance_)
    statuses->push_back(guidanceStatus());
  if (health_monitor_)
    statuses->push_back(healthStatus());
}

double SessionAssistant::healthStatistic() const
{
  return health_monitor_ ? health_monitor_->status().statistic : 0.0;
}

AssistantMarker SessionAssistant::marker() const
{
  AssistantMarker marker;
  if (guidance_) {
    const ExcitationStatus guidance = guidance_->status();
    marker.ready = guidance.ready_to_fit;
    marker.text = guidance.ready_to_fit
                      ? "calibration: ready to fit (call ~calibrate)"
                      : "calibration: collecting (" + std::to_string(guidance.pairs) + " pairs)";
    for (std::size_t i = 0; i < guidance.missing_motions.size() && i < 3; ++i)
      marker.text += "\n" + guidance.missing_motions[i];
  }
  if (health_monitor_) {
    const HealthStatus health = health_monitor_->status();
    marker.alarm = health.alarm;
    char line[80];
    std::snprintf(line, sizeof(line), "calibration health: ok (statistic %.2f of 1)",
                  health.statistic);
    marker.text += std::string(marker.text.empty() ? "" : "\n") +
                   (health.alarm ? "CALIBRATION STALE: " + health.message : std::string(line));
  }
  return marker;
}

}  // namespace odometry_calibration
