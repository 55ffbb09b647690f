// The live node's assistant (issue 18): what to drive next before a fit (excitation guidance),
// whether the active calibration still fits the robot after it (health monitor). Both are the
// core's (models/excitation_guidance.h, models/health_monitor.h); this file only wires them to
// ~parameters, /diagnostics, an rviz text marker and ~health_statistic.
#include <cmath>
#include <cstdio>

#include <std_msgs/Float64.h>
#include <visualization_msgs/Marker.h>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/ros/calibration_node.h"

namespace odometry_calibration {

AssistantOptions readAssistantOptions(const ros::NodeHandle& p)
{
  AssistantOptions o;
  ExcitationGuidanceOptions& g = o.guidance_options;
  HealthMonitorOptions& h = o.health_options;
  p.param("guidance", o.guidance, o.guidance);
  p.param("guidance_marker_height_m", o.marker_height_m, o.marker_height_m);
  p.param("guidance_marker_text_m", o.marker_text_height_m, o.marker_text_height_m);
  p.param("guidance_relative_target", g.relative_target, g.relative_target);
  p.param("guidance_length_target_m", g.length_target_m, g.length_target_m);
  p.param("guidance_angle_target_rad", g.angle_target_rad, g.angle_target_rad);
  p.param("guidance_straight_distance_m", g.straight_distance_m, g.straight_distance_m);
  p.param("guidance_spot_turn_rad", g.spot_turn_rad, g.spot_turn_rad);
  p.param("guidance_turn_rad", g.turn_rad, g.turn_rad);
  p.param("guidance_strafe_distance_m", g.strafe_distance_m, g.strafe_distance_m);
  p.param("guidance_full_lock_rad", g.full_lock_rad, g.full_lock_rad);
  p.param("guidance_full_lock_travel_m", g.full_lock_travel_m, g.full_lock_travel_m);
  std::map<std::string, double> targets;
  if (p.getParam("guidance_target_sigma", targets))
    g.target_sigma = targets;
  else if (p.hasParam("guidance_target_sigma"))
    throw std::invalid_argument(
        "~guidance_target_sigma must map parameter names to sigmas, e.g. {wheel_separation: "
        "0.0005}");
  p.param("health_monitor", o.health_monitor, o.health_monitor);
  p.param("health_false_alarm_pairs", h.false_alarm_pairs, h.false_alarm_pairs);
  p.param("health_design_shift_sigma", h.design_shift_sigma, h.design_shift_sigma);
  p.param("health_burn_in_pairs", h.burn_in_pairs, h.burn_in_pairs);
  try {
    validate(g);
    validate(h);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("~guidance_* / ~health_* parameters: ") + error.what());
  }
  if (!(o.marker_height_m >= 0.0) || !(o.marker_text_height_m > 0.0))
    throw std::invalid_argument(
        "~guidance_marker_height_m must be >= 0 m and ~guidance_marker_text_m > 0 m");
  return o;
}

void CalibrationNode::setUpAssistant()
{
  assistant_options_ = readAssistantOptions(private_handle_);
  guidance_marker_publisher_ =
      private_handle_.advertise<visualization_msgs::Marker>("guidance_marker", 1, true);
  health_statistic_publisher_ =
      private_handle_.advertise<std_msgs::Float64>("health_statistic", 10);
  if (assistant_options_.guidance) {
    // The fitted model's guidance, or the prior model's when the fitted one has none (gp).
    const std::string name =
        hasExcitationGuidance(config_.model) ? config_.model : config_.prior_model;
    if (!hasExcitationGuidance(name)) {
      ROS_INFO(
          "no excitation guidance: it needs a diff_drive, tricycle or mecanum model or "
          "prior_model");
    } else {
      try {
        const CalibrationConfig for_model =
            configForModel(config_text_, name, "", options_.config_path);
        guidance_ =
            makeExcitationGuidance(name, for_model.models, assistant_options_.guidance_options);
        guidance_model_ = name;
        guidance_factory_ = for_model.models;
        for (const MotionPair& pair : pairs_)
          guidance_->addPair(pair);
      } catch (const std::exception& error) {
        ROS_WARN("no excitation guidance for %s: %s", name.c_str(), error.what());
        guidance_.reset();
      }
    }
  }
  if (active_model_ && active_model_origin_.rfind("nominal", 0) != 0)
    startHealthMonitor(active_model_);
}

void CalibrationNode::recordEncoderHistory(double stamp_s, const Eigen::VectorXd& accepted)
{
  if (!config_.estimate_time_offset)
    return;
  if (!history_decoder_)
    history_decoder_ = std::make_unique<EncoderDecoder>(channels_);
  if (!encoder_history_.empty() && stamp_s <= encoder_history_.back().stamp_s) {
    if (stamp_s == encoder_history_.back().stamp_s)
      return;  // a repeated stamp adds nothing
    // Time went backwards (a restarted bag): the offset search needs one continuous stream.
    encoder_history_.clear();
    history_decoder_->reset();
  }
  encoder_history_.push_back({stamp_s, history_decoder_->decode(accepted)});
}

void CalibrationNode::applyTimeOffset(double time_offset_s)
{
  const double previous_s = config_.collector.time_offset_s;
  if (std::abs(time_offset_s - previous_s) < 1e-6)
    return;
  config_.collector.time_offset_s = time_offset_s;
  collector_ =
      std::make_unique<PairCollector>(channels_, config_.collector, priorPredictor(config_));
  if (candidates_) {  // the fit-interval candidates pair at the new offset too
    std::vector<double> other_intervals;
    for (const double interval : config_.fit_intervals_s) {
      if (std::abs(interval - config_.collector.keyframe_interval_s) > 1e-9)
        other_intervals.push_back(interval);
    }
    candidates_ = std::make_unique<CandidateCollectors>(channels_, config_.collector,
                                                        priorPredictor(config_), other_intervals);
  }
  restartOdometry();
  ROS_INFO("time offset %.4f s -> %.4f s: new pairs and the odometry use it (both restarted)",
           previous_s, time_offset_s);
}

std::string timeOffsetSentence(const CalibrationConfig& config, const CalibrationJobResult& job,
                               bool no_history)
{
  if (!config.estimate_time_offset)
    return "";
  char text[200];
  if (no_history) {
    std::snprintf(text, sizeof(text),
                  " Time offset: not estimated (no continuous encoder history since the start or "
                  "the last ~reset), kept %.4f s.",
                  job.time_offset_s);
  } else if (!job.time_offset || job.time_offset->flat) {
    std::snprintf(text, sizeof(text),
                  " Time offset: not observable from this drive (flat cost), kept %.4f s.",
                  job.time_offset_s);
  } else {
    std::snprintf(text, sizeof(text),
                  " Time offset: tau = %.4f +- %.4f s (encoder values at scan time + tau), used "
                  "for new pairs.",
                  job.time_offset_s, job.time_offset->sigma_s);
  }
  return text;
}

void CalibrationNode::assistantAddPair(const MotionPair& pair)
{
  if (guidance_)
    guidance_->addPair(pair);
  if (health_monitor_ && health_monitor_->addPair(pair)) {
    ROS_WARN("calibration health: %s", health_monitor_->status().message.c_str());
  }
}

void CalibrationNode::startHealthMonitor(const std::shared_ptr<const MotionModel>& model)
{
  if (!assistant_options_.health_monitor || !model)
    return;
  health_monitor_ = std::make_unique<HealthMonitor>(model, assistant_options_.health_options);
  health_model_origin_ = active_model_origin_;
}

void CalibrationNode::recentreGuidance(const std::string& model, const ModelReport& report)
{
  if (!guidance_ || model != guidance_model_)
    return;
  try {
    auto recentred = makeExcitationGuidance(model, guidance_factory_,
                                            assistant_options_.guidance_options, report.parameters);
    for (const MotionPair& pair : pairs_)
      recentred->addPair(pair);
    guidance_ = std::move(recentred);
  } catch (const std::exception& error) {
    ROS_WARN("the guidance stays at its previous values: %s", error.what());
  }
}

void CalibrationNode::resetAssistant()
{
  if (guidance_)
    guidance_->reset();
  encoder_history_.clear();
  if (history_decoder_)
    history_decoder_->reset();
}

std::string CalibrationNode::guidanceSummary() const
{
  return guidance_ ? " Guidance: " + guidance_->status().summary() + "." : std::string();
}

void CalibrationNode::publishAssistant(std::vector<diagnostic_msgs::DiagnosticStatus>& statuses)
{
  std::string marker_text;
  auto add = [](diagnostic_msgs::DiagnosticStatus& status, const std::string& key,
                const std::string& value) {
    diagnostic_msgs::KeyValue entry;
    entry.key = key;
    entry.value = value;
    status.values.push_back(entry);
  };
  char number[64];
  auto format = [&number](double value) {
    std::snprintf(number, sizeof(number), "%.4g", value);
    return std::string(number);
  };
  if (guidance_) {
    const ExcitationStatus guidance = guidance_->status();
    diagnostic_msgs::DiagnosticStatus status;
    status.name = ros::this_node::getName() + ": excitation guidance";
    status.hardware_id = sensorFrame();
    status.level = diagnostic_msgs::DiagnosticStatus::OK;
    status.message = guidance.summary();
    add(status, "guidance model", guidance.model);
    add(status, "ready to fit", guidance.ready_to_fit ? "true" : "false");
    for (std::size_t i = 0; i < guidance.missing_motions.size(); ++i)
      add(status, "missing motion " + std::to_string(i + 1), guidance.missing_motions[i]);
    for (const ParameterGuidance& p : guidance.parameters) {
      add(status, p.name + " [" + p.unit + "]",
          (p.enough ? "enough: sigma " : "collecting: sigma ") + format(p.sigma) + " (target " +
              format(p.target_sigma) + ")");
    }
    statuses.push_back(status);
    marker_text = guidance.ready_to_fit
                      ? "calibration: ready to fit (call ~calibrate)"
                      : "calibration: collecting (" + std::to_string(guidance.pairs) + " pairs)";
    for (std::size_t i = 0; i < guidance.missing_motions.size() && i < 3; ++i)
      marker_text += "\n" + guidance.missing_motions[i];
  }
  bool alarm = false;
  if (health_monitor_) {
    const HealthStatus health = health_monitor_->status();
    alarm = health.alarm;
    diagnostic_msgs::DiagnosticStatus status;
    status.name = ros::this_node::getName() + ": calibration health";
    status.hardware_id = sensorFrame();
    status.level = health.alarm ? diagnostic_msgs::DiagnosticStatus::WARN
                                : diagnostic_msgs::DiagnosticStatus::OK;
    status.message = health.message;
    add(status, "watching", health_model_origin_);
    add(status, "statistic (alarm at 1)", format(health.statistic));
    add(status, "CUSUM threshold h [sigma]", format(health.threshold));
    add(status, "pairs scored", std::to_string(health.pairs));
    for (const HealthChart& chart : health.charts) {
      add(status, "chart " + chart.name + " (" + chart.output + ")",
          chart.calibrated ? "U " + format(chart.upper) + ", L " + format(chart.lower) +
                                 ", recent mean " + format(chart.mean_recent) + " sigma"
                           : "learning the noise (" + std::to_string(chart.count) + " pairs)");
    }
    statuses.push_back(status);
    std_msgs::Float64 statistic;
    statistic.data = health.statistic;
    health_statistic_publisher_.publish(statistic);
    char line[80];
    std::snprintf(line, sizeof(line), "calibration health: ok (statistic %.2f of 1)",
                  health.statistic);
    marker_text += std::string(marker_text.empty() ? "" : "\n") +
                   (health.alarm ? "CALIBRATION STALE: " + health.message : std::string(line));
  }
  if (marker_text.empty())
    return;
  visualization_msgs::Marker marker;
  marker.header.stamp = ros::Time::now();
  marker.header.frame_id = options_.base_frame;
  marker.ns = "odometry_calibration";
  marker.id = 0;
  marker.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  marker.action = visualization_msgs::Marker::ADD;
  marker.pose.position.z = assistant_options_.marker_height_m;
  marker.pose.orientation.w = 1.0;
  marker.scale.z = assistant_options_.marker_text_height_m;
  // Dark colours (rviz/calibration.rviz has a white background): red for a stale calibration,
  // green when ready to fit, orange while collecting.
  const bool ready = guidance_ && guidance_->status().ready_to_fit;
  marker.color.a = 1.0;
  marker.color.r = alarm ? 0.85f : (ready ? 0.0f : 0.8f);
  marker.color.g = alarm ? 0.0f : (ready ? 0.5f : 0.4f);
  marker.color.b = 0.0f;
  marker.text = marker_text;
  guidance_marker_publisher_.publish(marker);
}

}  // namespace odometry_calibration
