// The session's actions: calibrate (a fit that becomes the active model), save, reset.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/report/controller_yaml.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Beyond this difference [s] between the estimated time offset and the pairs', the reply says
/// how to get pairs made at the estimate (calibrate_bag pairs again beyond it too).
constexpr double kRepairingToleranceS = 0.01;

/// `text` ended as a sentence: a full stop added unless it ends with one (or ! or ?).
std::string asSentence(std::string text)
{
  if (!text.empty() && text.back() != '.' && text.back() != '!' && text.back() != '?')
    text += '.';
  return text;
}

std::string absolutePath(const std::string& directory, const std::string& name)
{
  return fs::absolute(directory + "/" + name).lexically_normal().string();
}

/// When the estimated offset is far from the one the pairs were made at: what to do for pairs
/// made at the estimate (their scans' sweep compensation and the matchers' guesses use it).
std::string repairingAdvice(double paired_at_s, const SessionFit& fit)
{
  if (!fit.offset_estimated || !fit.job.time_offset || fit.job.time_offset->flat ||
      !(std::abs(fit.job.time_offset_s - paired_at_s) > kRepairingToleranceS))
    return "";
  char text[400];
  std::snprintf(text, sizeof(text),
                " The pairs so far were made at time offset %.3f s: for pairs made at the "
                "estimate, set keyframes.time_offset_s: %.3f, or ~reset and drive again (new "
                "pairs use it; calibrate_bag pairs a bag again at it).",
                paired_at_s, fit.job.time_offset_s);
  return text;
}

}  // namespace

SessionFitRequest CalibrationSession::snapshot(std::string* guidance) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  SessionFitRequest fit_request;
  fit_request.config = config_;
  fit_request.pairs = store_->pairs();
  if (candidates_)
    fit_request.candidates = candidates_->pairs();
  if (!history_broken_)
    fit_request.encoder_history = encoder_history_;
  fit_request.compare_trajectories = options_.compare_trajectories;
  *guidance = assistant_ ? assistant_->guidanceSummary() : std::string();
  return fit_request;
}

void CalibrationSession::configureModel(const std::string& name, const std::string& options,
                                        CalibrationConfig* config) const
{
  requireKnownModel(name, "model");
  // The model sections as this model needs them (its joints resolved and checked); the
  // configuration's own model has them already.
  if (name != config->model || !options.empty()) {
    if (config_text_.empty())
      throw std::invalid_argument("the session has no configuration text to read it from");
    config->models = configForModel(config_text_, name, options, config_source_).models;
  }
  config->model = name;
}

CalibrateOutcome CalibrationSession::calibrate(const CalibrationRequest& request)
{
  // One fit (or reset) at a time; the inputs go on meanwhile (they take mutex_ only).
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  CalibrateOutcome outcome;
  std::string guidance;
  SessionFitRequest fit_request = snapshot(&guidance);
  outcome.pairs_collected = fit_request.pairs.size();
  const std::string name = request.model.empty() ? fit_request.config.model : request.model;
  if (const std::string conflict = counts().publisher_conflict; !conflict.empty()) {
    outcome.message = "cannot calibrate: " + conflict;
    return outcome;
  }
  try {
    configureModel(name, request.options, &fit_request.config);
  } catch (const std::exception& error) {
    outcome.message =
        "cannot fit " + name + " with this configuration and options: " + error.what();
    return outcome;
  }
  if (static_cast<int>(fit_request.pairs.size()) < options_.min_pairs) {
    outcome.message =
        "only " + std::to_string(fit_request.pairs.size()) + " pairs collected, " +
        std::to_string(options_.min_pairs) + " needed" +
        (options_.min_pairs_name.empty() ? "" : " (" + options_.min_pairs_name + ")") +
        ": drive more, straight and turning both ways." + guidance;
    return outcome;
  }
  fit_request.interval_mode = request.interval_mode.value_or(
      fit_request.candidates.empty() ? FitIntervalMode::kConfigured : FitIntervalMode::kChoose);
  fit_request.fixed_interval_s = request.fixed_interval_s;
  fit_request.fit_until_stamp_s = request.fit_until_stamp_s;
  fit_request.offset_search = request.offset_search;
  try {
    outcome.fit = fitSessionPairs(fit_request);
  } catch (const std::exception& error) {
    outcome.message = name + " fit failed: " + error.what();
    return outcome;
  }
  adopt(name, fit_request.config, guidance, &outcome);
  return outcome;
}

CalibrateOutcome CalibrationSession::adoptFit(const SessionFit& fit, std::size_t pairs_collected)
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  CalibrateOutcome outcome;
  outcome.pairs_collected = pairs_collected;
  outcome.fit = fit;
  std::string guidance;
  const CalibrationConfig config = snapshot(&guidance).config;
  adopt(config.model, config, guidance, &outcome, true);
  return outcome;
}

void CalibrationSession::adopt(const std::string& name, const CalibrationConfig& config,
                               const std::string& guidance, CalibrateOutcome* outcome, bool always)
{
  const SessionFit& fit = *outcome->fit;
  if (!fit.job.report.converged) {
    outcome->message = name + " fit did not converge (" + fit.job.report.termination +
                       "); the active model is unchanged";
    return;
  }
  if (!options_.adopt_fits && !always) {  // calibrate_bag: the fit is the result, nothing runs on
    outcome->success = true;
    outcome->message = successMessage(name, fit);
    return;
  }
  const std::string result_yaml =
      calibrationResultYaml(fit.job.report, *fit.job.model, options_.source, fit.job.time_offset_s,
                            jointLayout(config).names, fit.fit_interval_s);
  if (!options_.output_directory.empty()) {
    try {
      // Every fit is kept (last_fit.yaml); save() makes it the calibration loaded on start.
      writeFileAtomically(options_.output_directory + "/last_fit.yaml", result_yaml);
    } catch (const std::exception& error) {
      say(SessionLogLevel::kError, std::string("cannot write last_fit.yaml: ") + error.what());
    }
  }
  try {
    OdometryReplay replay = replayOdometry(fit);
    std::lock_guard<std::mutex> lock(mutex_);
    activate(name, fit, fit.job.model, result_yaml, std::move(replay));
  } catch (const std::exception& error) {
    outcome->message = name + " fitted, but its odometry failed: " + error.what() +
                       "; the active model is unchanged";
    return;
  }
  outcome->success = true;
  outcome->message = successMessage(name, fit) + timeOffsetSentence(config, fit) +
                     repairingAdvice(config.collector.time_offset_s, fit);
  for (const std::string& warning : fit.job.report.warnings)
    outcome->message += " WARNING: " + asSentence(warning);
  outcome->message += guidance;
}

std::string CalibrationSession::successMessage(const std::string& name, const SessionFit& fit) const
{
  const ModelReport& report = fit.job.report;
  std::string message =
      name + " fitted to " + std::to_string(report.pairs_used) + " pairs (" +
      std::to_string(report.rejected) + " rejected, " + std::to_string(report.down_weighted) +
      " down-weighted); residual RMS per pair " +
      (report.before.count > 0 ? std::to_string(report.before.translation_m) + " -> "
                               : std::string()) +
      std::to_string(report.after.translation_m) + " m. Now driving ~odom; call ~save to keep it.";
  if (!fit.interval_text.empty())
    message += " " + fit.interval_text + ".";
  return message;
}

OdometryReplay CalibrationSession::replayOdometry(const SessionFit& fit) const
{
  // The corrected odometry is integrated again over the kept samples with the new model, so
  // that ~odom and its path show the calibrated trajectory (one jump at the fit); the samples
  // are copied under the lock and integrated without it, so that the inputs keep flowing.
  OdometryReplayInput input;
  std::optional<Pose2> T_base_sensor;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!odometry_)
      return {};
    input = odometry_->replayInput();
    T_base_sensor = fitSensorPose(fit);
  }
  auto integrator =
      std::make_unique<OdometryIntegrator>(fit.job.model, T_base_sensor, fit.fit_interval_s);
  integrator->setWindowCovarianceFloor(config_.collector.covariance_floor.asDiagonal());
  return SessionOdometry::replay(input, std::move(integrator));
}

std::optional<Pose2> CalibrationSession::fitSensorPose(const SessionFit& fit) const
{
  const ModelReport& report = fit.job.report;
  return report.has_extrinsic ? std::optional<Pose2>(report.T_base_sensor) : T_base_sensor_;
}

void CalibrationSession::activate(const std::string& name, const SessionFit& fit,
                                  const std::shared_ptr<MotionModel>& model,
                                  const std::string& result_yaml, OdometryReplay replay)
{
  const ModelReport& report = fit.job.report;
  const std::optional<Pose2> T_base_sensor = fitSensorPose(fit);
  if (odometry_ && replay.integrator)
    odometry_->replayFinish(std::move(replay));
  T_base_sensor_ = T_base_sensor;
  fitted_model_ = model;
  fitted_result_yaml_ = result_yaml;
  fitted_controller_yaml_ = controllerYaml(report, options_.source);
  model_interval_s_ = fit.fit_interval_s;
  active_model_ = model;
  active_model_origin_ = "fit of " + std::to_string(report.pairs_used) + " pairs";
  last_fit_counts_ = {report.pairs_used, report.rejected, report.down_weighted};
  notifySensorPose();
  applyTimeOffset(fit.job.time_offset_s);
  if (assistant_) {
    assistant_->watch(model, active_model_origin_);
    assistant_->recentre(name, report, store_->pairs());
  }
}

void CalibrationSession::applyTimeOffset(double time_offset_s)
{
  const double previous_s = config_.collector.time_offset_s;
  if (std::abs(time_offset_s - previous_s) < 1e-6)
    return;
  config_.collector.time_offset_s = time_offset_s;
  makeCollectors();  // the fit-interval candidates pair at the new offset too
  if (odometry_)
    odometry_->restart();
  char text[200];
  std::snprintf(text, sizeof(text),
                "time offset %.4f s -> %.4f s: new pairs and the odometry use it (both restarted)",
                previous_s, time_offset_s);
  say(SessionLogLevel::kInfo, text);
}

std::pair<bool, std::string> CalibrationSession::save()
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!fitted_model_)
    return {false, "nothing to save: no successful ~calibrate since the node started"};
  if (options_.output_directory.empty())
    return {false, "nothing to save: the session has no output directory"};
  const std::string& directory = options_.output_directory;
  try {
    const std::string result_path = absolutePath(directory, "result.yaml");
    writeFileAtomically(result_path, fitted_result_yaml_);
    std::string message = "saved " + result_path;
    const std::string controller_path = absolutePath(directory, "controller.yaml");
    if (!fitted_controller_yaml_.empty()) {
      writeFileAtomically(controller_path, fitted_controller_yaml_);
      message += ", " + controller_path;
    } else {  // an earlier calibration's controller values must not pass for this one's
      std::error_code ignored;
      fs::remove(controller_path, ignored);
    }
    if (T_base_sensor_) {
      const std::string urdf_path = absolutePath(directory, "laser_joint.urdf");
      const std::string frame =
          sensor_frame_.empty() ? options_.default_sensor_frame : sensor_frame_;
      writeFileAtomically(urdf_path, laserJointUrdf(*T_base_sensor_, options_.base_frame, frame));
      message += " and " + urdf_path;
    }
    return {true, message};
  } catch (const std::exception& error) {
    return {false, std::string("cannot save: ") + error.what()};
  }
}

std::pair<bool, std::string> CalibrationSession::reset()
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);  // not while a fit of these pairs runs
  std::lock_guard<std::mutex> lock(mutex_);
  std::string set_aside;
  try {
    set_aside = store_->reset();
  } catch (const std::exception& error) {
    return {false, std::string("cannot set the pairs aside (") + error.what() +
                       "): nothing was reset, the pairs are kept"};
  }
  collector_->reset();
  if (candidates_)
    candidates_->clear();
  if (odometry_)
    odometry_->restart();
  if (assistant_)
    assistant_->reset();
  encoder_history_.clear();
  history_broken_ = false;
  if (history_decoder_)
    history_decoder_->reset();
  return {true, "collection restarted: " + set_aside + "; the active model is kept"};
}

}  // namespace odometry_calibration
