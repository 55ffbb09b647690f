// The session's actions: calibrate (a fit that becomes the active model; a fit made elsewhere
// adopted in steps), save, reset.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/calibration/held_out_comparison.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/eval/model_adequacy.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/session/calibration_session.h"
#include "odometry_calibration/session/pairing_explanation.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// `text` ended as a sentence: a full stop added unless it ends with one (or ! or ?).
std::string asSentence(std::string text)
{
  if (!text.empty() && text.back() != '.' && text.back() != '!' && text.back() != '?')
    text += '.';
  return text;
}

/// The reply's held-out table of `fit` (compareHeldOut on its pairs, the fitted model and
/// compare_models of `request.config`), or why there is none, then the adequacy check of a
/// parametric fit (eval/model_adequacy.h) with the model the table recommends.
std::string heldOutText(const SessionFitRequest& request, const SessionFit& fit, double fraction)
{
  std::string text;
  HeldOutComparison comparison;
  try {
    comparison = compareHeldOut(request.config, fit.job, fraction, request.encoder_history);
    text = formatHeldOutComparison(comparison, fraction);
  } catch (const std::exception& error) {
    text = std::string("no held-out table: ") + error.what() + "\n";
  }
  if (fit.job.report.parameters.empty())
    return text;
  const AdequacyCheck check = checkModelAdequacy(*fit.job.model, fit.job.pairs);
  return text + check.text +
         adequacyAdvice(check, request.config.model, comparison.scores, "the held-out pairs");
}

std::string absolutePath(const std::string& directory, const std::string& name)
{
  return fs::absolute(directory + "/" + name).lexically_normal().string();
}

/// When the estimated offset is far from the one the pairs were made at: what to do for pairs
/// made at the estimate (their scans' sweep compensation and the matchers' guesses use it).
std::string pairingAgainAdvice(double paired_at_s, const SessionFit& fit)
{
  if (!fit.offset_estimated || !fit.job.time_offset || fit.job.time_offset->flat ||
      !(std::abs(fit.job.time_offset_s - paired_at_s) > kOffsetPairingToleranceS))
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

SessionFitRequest CalibrationSession::snapshot(std::string* guidance,
                                               std::optional<InputRecordView>* record,
                                               std::size_t* resumed)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (record && record_) {
    try {
      *record = record_->view();
    } catch (const std::exception& error) {
      dropRecord(error.what());
    }
  }
  if (resumed)
    *resumed = store_->resumed();
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

void CalibrationSession::configureModel(const std::string& name, const CalibrationRequest& request,
                                        CalibrationConfig* config) const
{
  requireKnownModel(name, "model");
  if (request.models) {
    config->models = *request.models;
    config->model = name;
    return;
  }
  const std::string& options = request.options;
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
  {
    std::lock_guard<std::mutex> lock(mutex_);
    completeWhenInputEnded();
  }
  CalibrateOutcome outcome;
  std::string guidance;
  std::optional<InputRecordView> record;
  std::size_t resumed = 0;
  SessionFitRequest fit_request = snapshot(&guidance, &record, &resumed);
  outcome.pairs_collected = fit_request.pairs.size();
  const std::string name = request.model.empty() ? fit_request.config.model : request.model;
  const SessionCounts input_counts = counts();
  for (const std::string* conflict :
       {&input_counts.publisher_conflict, &input_counts.configuration_conflict}) {
    if (!conflict->empty()) {
      outcome.message = "cannot calibrate: " + *conflict;
      return outcome;
    }
  }
  if (const std::string problem = oneStampProblem(); !problem.empty()) {
    outcome.message = "cannot calibrate: " + problem;
    return outcome;
  }
  try {
    configureModel(name, request, &fit_request.config);
  } catch (const std::exception& error) {
    outcome.message =
        "cannot fit " + name + " with this configuration and options: " + error.what();
    return outcome;
  }
  if (static_cast<int>(fit_request.pairs.size()) < options_.min_pairs) {
    outcome.message =
        explainTooFewPairs(input_counts.statistics, fit_request.config.collector,
                           fit_request.pairs.size(), static_cast<std::size_t>(options_.min_pairs)) +
        (options_.min_pairs_name.empty() ? ""
                                         : " (" + options_.min_pairs_name + " sets how many.)") +
        guidance;
    return outcome;
  }
  try {
    outcome.fit = fitPairs(request, record, resumed, &fit_request);
  } catch (const std::exception& error) {
    outcome.message = name + " fit failed: " + error.what();
    return outcome;
  }
  outcome.pairs_collected = fit_request.pairs.size();
  const std::string pairing = outcome.fit->offset_pairing.text;
  adopt(name, fit_request.config, guidance, &outcome);  // may make a new outcome
  if (!pairing.empty())
    outcome.message += " Pairs: " + pairing.substr(0, pairing.size() - 1) + ".";
  if (outcome.success && request.reply_holdout_fraction > 0.0)
    outcome.message +=
        "\n" + heldOutText(fit_request, *outcome.fit, request.reply_holdout_fraction);
  return outcome;
}

/// What a fit changes in a session when it becomes the active model, and what it needs for the
/// rest of its adoption; after the commit, the session's previous state (exchangeActive).
struct PreparedAdoption::State
{
  std::string name;
  CalibrationConfig config;
  SessionFit fit;
  std::string guidance;
  bool committed = false;
  // Exchanged with the session's by exchangeActive.
  std::shared_ptr<const MotionModel> active_model, fitted_model;
  std::string origin;
  FileSet files;  ///< calibrationFiles of the fit
  double model_interval_s = 0.0;
  std::optional<CalibrationSession::FitCounts> counts;
  std::optional<Pose2> T_base_sensor;
  double time_offset_s = 0.0;
  /// The collectors at the new time offset; none when it does not change.
  std::unique_ptr<PairCollector> collector;
  std::unique_ptr<CandidateCollectors> candidates;
  bool new_offset = false;  ///< the fit's time offset is not the session's
  OdometryReplay replay;
  /// With a new time offset, the odometry the exchange did not leave active: before the
  /// commit, none; after it, the one the commit replaced (a copy taken before it restarted),
  /// which a roll-back puts back as it was.
  std::unique_ptr<SessionOdometry> other_odometry;
};

PreparedAdoption::PreparedAdoption() = default;
PreparedAdoption::PreparedAdoption(PreparedAdoption&&) noexcept = default;
PreparedAdoption& PreparedAdoption::operator=(PreparedAdoption&&) noexcept = default;
PreparedAdoption::~PreparedAdoption() = default;

PreparedAdoption CalibrationSession::prepareAdoption(const SessionFit& fit, const std::string& name,
                                                     const ModelFactoryOptions& models)
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  std::string guidance;
  CalibrationConfig config = snapshot(&guidance).config;
  config.model = name;
  config.models = models;
  return prepare(fit, name, config, guidance);
}

void CalibrationSession::commitAdoption(PreparedAdoption& adoption)
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  commit(adoption);
}

void CalibrationSession::rollBackAdoption(PreparedAdoption& adoption)
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  std::lock_guard<std::mutex> lock(mutex_);
  rollBack(adoption);
}

CalibrateOutcome CalibrationSession::finishAdoption(PreparedAdoption& adoption,
                                                    std::size_t pairs_collected)
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  return finish(adoption, pairs_collected);
}

PreparedAdoption CalibrationSession::prepare(const SessionFit& fit, const std::string& name,
                                             const CalibrationConfig& config,
                                             const std::string& guidance) const
{
  const ModelReport& report = fit.job.report;
  if (!report.converged)
    throw std::invalid_argument(name + " fit did not converge (" + report.termination + ")");
  PreparedAdoption adoption;
  adoption.state_ = std::make_unique<PreparedAdoption::State>();
  PreparedAdoption::State& state = *adoption.state_;
  state.name = name;
  state.config = config;
  state.fit = fit;
  state.guidance = guidance;
  state.active_model = state.fitted_model = fit.job.model;
  state.origin = "fit of " + std::to_string(report.pairs_used) + " pairs";
  state.model_interval_s = fit.fit_interval_s;
  state.counts = FitCounts{report.pairs_used, report.rejected, report.down_weighted};
  state.time_offset_s = fit.job.time_offset_s;
  CollectorOptions collector;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    state.T_base_sensor = fitSensorPose(fit);
    collector = config_.collector;
    state.files = calibrationFiles(
        {&report, fit.job.model.get(), options_.source, fit.job.time_offset_s,
         jointLayout(config).names, fit.fit_interval_s, state.T_base_sensor, options_.base_frame,
         sensor_frame_.empty() ? options_.default_sensor_frame : sensor_frame_});
  }
  try {
    state.replay = replayOdometry(fit);
  } catch (const std::exception& error) {
    throw std::runtime_error(std::string("its odometry failed: ") + error.what());
  }
  // Within the pairing tolerance the offset stays: new pairs are made as the fitted ones were,
  // and the odometry's path goes on.
  if (std::abs(fit.job.time_offset_s - collector.time_offset_s) > kOffsetPairingToleranceS) {
    state.new_offset = true;
    collector.time_offset_s = fit.job.time_offset_s;
    try {  // the fit-interval candidates pair at the new offset too
      buildCollectors(collector, &state.collector, &state.candidates);
    } catch (const std::exception& error) {
      throw std::runtime_error(std::string("its time offset cannot be paired at: ") + error.what());
    }
  }
  return adoption;
}

void CalibrationSession::exchangeActive(PreparedAdoption& adoption)
{
  PreparedAdoption::State& state = *adoption.state_;
  if (state.new_offset && state.other_odometry) {
    // A new time offset exchanged back (or again): the odometry as it was, with its path and
    // pose (only what arrived since the exchange is missing, taken as one step by the next).
    std::swap(odometry_, state.other_odometry);
  } else if (odometry_) {
    // Copied before it changes: with a new offset the odometry restarts below.
    std::unique_ptr<SessionOdometry> before =
        state.new_offset ? std::make_unique<SessionOdometry>(*odometry_) : nullptr;
    odometry_->swapCorrected(&state.replay);  // with the copy, the steps that may throw: first
    if (state.new_offset) {
      odometry_->restart();  // a new time offset: the odometry starts at it
      state.other_odometry = std::move(before);
    }
  }
  std::swap(active_model_, state.active_model);
  std::swap(fitted_model_, state.fitted_model);
  std::swap(active_model_origin_, state.origin);
  std::swap(fitted_files_, state.files);
  std::swap(model_interval_s_, state.model_interval_s);
  std::swap(last_fit_counts_, state.counts);
  std::swap(T_base_sensor_, state.T_base_sensor);
  if (state.new_offset) {  // a new time offset: new pairs start at it
    std::swap(config_.collector.time_offset_s, state.time_offset_s);
    std::swap(collector_, state.collector);
    std::swap(candidates_, state.candidates);
  }
  state.committed = !state.committed;
}

void CalibrationSession::adopt(const std::string& name, const CalibrationConfig& config,
                               const std::string& guidance, CalibrateOutcome* outcome)
{
  const SessionFit& fit = *outcome->fit;
  if (!fit.job.report.converged) {
    outcome->message = name + " fit did not converge (" + fit.job.report.termination +
                       "); the active model is unchanged";
    return;
  }
  if (!options_.adopt_fits) {  // calibrate_bag: the fit is the result, nothing runs on
    outcome->success = true;
    outcome->message = successMessage(name, fit);
    return;
  }
  PreparedAdoption adoption;
  try {
    adoption = prepare(fit, name, config, guidance);
    commit(adoption);
  } catch (const std::exception& error) {
    outcome->message = name + " fitted, but " + error.what() + "; the active model is unchanged";
    return;
  }
  *outcome = finish(adoption, outcome->pairs_collected);
}

void CalibrationSession::commit(PreparedAdoption& adoption)
{
  if (!adoption.state_ || adoption.state_->committed)
    throw std::logic_error("commitAdoption: no prepared fit (or committed already)");
  std::lock_guard<std::mutex> lock(mutex_);
  exchangeActive(adoption);  // throws before anything changed
  try {
    notifySensorPose();
  } catch (...) {
    rollBack(adoption);
    throw;
  }
}

void CalibrationSession::rollBack(PreparedAdoption& adoption)
{
  if (!adoption.state_ || !adoption.state_->committed)
    return;
  try {
    exchangeActive(adoption);
  } catch (const std::exception& error) {
    // The previous odometry cannot take the samples since the commit: it starts again (a
    // restart leaves it nothing to take).
    say(SessionLogLevel::kWarn,
        std::string("the odometry starts again with the previous model: ") + error.what());
    odometry_->restart();
    exchangeActive(adoption);
  }
  try {
    notifySensorPose();
  } catch (const std::exception& error) {
    say(SessionLogLevel::kError,
        std::string("cannot tell the previous sensor pose again: ") + error.what());
  }
}

CalibrateOutcome CalibrationSession::finish(PreparedAdoption& adoption, std::size_t pairs_collected)
{
  if (!adoption.state_ || !adoption.state_->committed)
    throw std::logic_error("finishAdoption: the fit is not committed");
  const PreparedAdoption::State& state = *adoption.state_;
  const SessionFit& fit = state.fit;
  CalibrateOutcome outcome;
  outcome.pairs_collected = pairs_collected;
  outcome.fit = fit;
  std::string result_yaml;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    result_yaml = fitted_files_.content(kResultFileName);
    if (state.new_offset) {  // exchanged: the state holds the previous offset
      char text[200];
      std::snprintf(text, sizeof(text),
                    "time offset %.4f s -> %.4f s: new pairs and the odometry use it (both "
                    "restarted)",
                    state.time_offset_s, config_.collector.time_offset_s);
      say(SessionLogLevel::kInfo, text);
    }
    if (assistant_) {
      assistant_->watch(active_model_, active_model_origin_);
      assistant_->recentre(state.name, fit.job.report, store_->pairs());
    }
  }
  if (!options_.output_directory.empty()) {
    try {
      // Every fit is kept (last_fit.yaml); save() makes it the calibration loaded on start.
      writeFileAtomically(options_.output_directory + "/last_fit.yaml", result_yaml);
    } catch (const std::exception& error) {
      say(SessionLogLevel::kError, std::string("cannot write last_fit.yaml: ") + error.what());
    }
  }
  outcome.success = true;
  outcome.message = successMessage(state.name, fit) + timeOffsetSentence(state.config, fit) +
                    pairingAgainAdvice(state.config.collector.time_offset_s, fit);
  for (const std::string& warning : fit.job.report.warnings)
    outcome.message += " WARNING: " + asSentence(warning);
  outcome.message += state.guidance;
  return outcome;
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

FileSet CalibrationSession::filesToSave() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!fitted_model_)
    throw std::runtime_error("nothing to save: no successful ~calibrate since the node started");
  return fitted_files_;
}

std::pair<bool, std::string> CalibrationSession::save()
{
  const std::string& directory = options_.output_directory;
  try {
    const FileSet files = filesToSave();
    if (directory.empty())
      return {false, "nothing to save: the session has no output directory"};
    writeFileSet(directory, files);  // all replaced, or none
    std::string message = "saved ";
    for (std::size_t f = 0; f < files.written.size(); ++f) {
      const bool urdf = files.written[f].first == kLaserJointFileName;
      message += (f == 0 ? ""
                  : urdf ? " and "
                         : ", ") +
                 absolutePath(directory, files.written[f].first);
    }
    return {true, message};
  } catch (const std::exception& error) {
    const std::string what = error.what();
    return {false, what.rfind("nothing to save", 0) == 0 ? what : "cannot save: " + what};
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
  input_since_flush_ = false;
  if (config_.estimate_time_offset) {
    try {
      if (record_)
        record_->clear();
      else
        record_ = std::make_unique<InputRecord>(options_.output_directory);
    } catch (const std::exception& error) {
      record_.reset();
      say(SessionLogLevel::kError, std::string("no input record (") + error.what() +
                                       "): the pairs cannot be made again at another time offset");
    }
  }
  return {true, "collection restarted: " + set_aside + "; the active model is kept"};
}

}  // namespace odometry_calibration
