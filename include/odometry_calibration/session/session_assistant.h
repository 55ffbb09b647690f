// The live assistant of a session (docs/live_assistant.md): excitation guidance while
// collecting (what to drive next, per parameter sigma against its target) and a health monitor
// of the active calibration after a fit (a CUSUM per output on each new pair's standardised
// residual). Both are the models' (excitation_guidance.h, health_monitor.h); this class feeds
// them the session's pairs and words their state for /diagnostics and an rviz marker.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/assistant/excitation_guidance.h"
#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/session/session_messages.h"

namespace odometry_calibration {

struct SessionAssistantOptions
{
  bool guidance = true;  ///< excitation guidance for the config's model (or prior_model)
  ExcitationGuidanceOptions guidance_options;
  bool health_monitor = true;  ///< watch a fitted or saved calibration
  HealthMonitorOptions health_options;
};

/// What an rviz text marker shows.
struct AssistantMarker
{
  std::string text;    ///< empty: nothing to show
  bool alarm = false;  ///< the health monitor found the calibration stale
  bool ready = false;  ///< the guidance says every parameter is determined
};

/// Not thread-safe: the session calls it with its lock held.
class SessionAssistant
{
public:
  /// `config_text` and `config_source` give the guidance model's configuration (its joints).
  SessionAssistant(const SessionAssistantOptions& options, const CalibrationConfig& config,
                   const std::string& config_text, const std::string& config_source,
                   SessionLog log);

  /// A pair of ego-motion source `source` (its index in egoMotionSources(config); 0 with one
  /// source). The guidance, made for the first source's pose, takes source 0's pairs only; a
  /// monitor watching one model scores source 0's pairs only.
  void addPair(const MotionPair& pair, std::size_t source = 0);
  /// Watches `model` from now on; `origin` says what it is ("fit of 480 pairs").
  void watch(const std::shared_ptr<const MotionModel>& model, const std::string& origin);
  /// Several sources: watches `models[s]` for source s (the joint calibration's
  /// wheels with that source's pose), each named by its frame (its topic without one). One
  /// model: as watch(). Throws std::invalid_argument when the count is not the sources'.
  void watch(const std::vector<std::shared_ptr<const MotionModel>>& models,
             const std::string& origin);
  /// After a fit of the guidance's model: the guidance linearised at the fitted values, fed
  /// `pairs` again.
  void recentre(const std::string& model, const ModelReport& report,
                const std::vector<MotionPair>& pairs);
  /// Forgets the guidance's pairs (a new collection); the monitor keeps watching.
  void reset();

  /// " Guidance: <summary>." for a reply ("" without guidance).
  std::string guidanceSummary() const;
  /// The excitation guidance and calibration health statuses (those that exist).
  void addStatuses(std::vector<SessionStatusReport>* statuses) const;
  AssistantMarker marker() const;
  bool watching() const { return health_monitor_ != nullptr; }
  /// The monitor's largest CUSUM over its threshold (alarm at 1); 0 when not watching.
  double healthStatistic() const;

private:
  SessionStatusReport guidanceStatus() const;
  SessionStatusReport healthStatus() const;

  SessionAssistantOptions options_;
  SessionLog log_;
  std::unique_ptr<ExcitationGuidance> guidance_;
  std::string guidance_model_;             ///< the model the guidance is for
  ModelFactoryOptions guidance_factory_;   ///< its options (joints resolved)
  std::vector<std::string> source_names_;  ///< each ego-motion source's frame or topic
  std::unique_ptr<HealthMonitor> health_monitor_;
  std::string health_model_origin_;  ///< what the monitor watches
  bool health_cause_told_ = false;   ///< the alarm's cause was logged with its quantity
};

}  // namespace odometry_calibration
