#include "odometry_calibration/session/joint_calibration_session.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/eval/joint_fit_text.h"
#include "odometry_calibration/report/controller_yaml.h"
#include "odometry_calibration/report/result_files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Source `index`'s options: its own directory, input name, frame; the joint fit adopted.
SessionOptions sourceOptions(const SessionOptions& options, const EgoMotionSourceConfig& source,
                             std::size_t index)
{
  SessionOptions own = options;
  if (!options.output_directory.empty())
    own.output_directory = options.output_directory + "/source_" + std::to_string(index);
  own.topics[1] = source.topic;
  own.default_sensor_frame = source.frame.empty()
                                 ? options.default_sensor_frame + "_" + std::to_string(index)
                                 : source.frame;
  own.adopt_fits = false;
  own.odometry = options.odometry && index == 0;
  if (options.log) {  // each source's lines name it (a laser whose pairs are rejected, ...)
    own.log = [log = options.log, topic = source.topic](SessionLogLevel level,
                                                        const std::string& text) {
      log(level, "[" + topic + "] " + text);
    };
  }
  return own;
}

/// "x 0.3001 m, y -0.0002 m, theta 0.0012 rad" of a sensor's pose.
std::string poseText(const Pose2& pose)
{
  char text[120];
  std::snprintf(text, sizeof(text), "(%.4f m, %.4f m, %.4f rad)", pose.x(), pose.y(), pose.theta());
  return text;
}

}  // namespace

JointCalibrationSession::JointCalibrationSession(
    const CalibrationConfig& config, const std::string& config_text,
    const std::string& config_source, const SessionOptions& options,
    const std::function<SessionListener(std::size_t)>& listener)
    : config_(config), options_(options), sources_(egoMotionSources(config))
{
  if (sources_.size() <= 1) {  // one source: its session exactly as before
    sessions_.push_back(std::make_unique<CalibrationSession>(
        config, config_text, config_source, options, listener ? listener(0) : SessionListener{}));
    return;
  }
  if (const std::string problem = jointFitModelProblem(config.model); !problem.empty())
    throw std::invalid_argument(problem);
  SessionAssistantOptions monitor_options = options.assistant_options;
  monitor_options.guidance = false;
  if (options.assistant && monitor_options.health_monitor) {
    monitor_ = std::make_unique<SessionAssistant>(monitor_options, config, config_text,
                                                  config_source, options.log);
  }
  for (std::size_t k = 0; k < sources_.size(); ++k) {
    SessionOptions own = sourceOptions(options, sources_[k], k);
    SessionListener own_listener = listener ? listener(k) : SessionListener{};
    if (monitor_) {  // the joint monitor, not the source's own, scores its pairs
      own.assistant_options.health_monitor = false;
      own_listener.pair = [this, k, forward = own_listener.pair](const MotionPair& pair) {
        monitorPair(pair, k);
        if (forward)
          forward(pair);
      };
    }
    sessions_.push_back(std::make_unique<CalibrationSession>(
        configForSource(config, k), config_text, config_source, own, own_listener));
  }
  watchSavedCalibrations();
}

JointCalibrationSession::~JointCalibrationSession() = default;

void JointCalibrationSession::addJointPositions(double stamp_s, const Eigen::VectorXd& raw,
                                                const std::string& publisher)
{
  for (const auto& session : sessions_)
    session->addJointPositions(stamp_s, raw, publisher);
}

void JointCalibrationSession::skipJointState(const std::string& problem,
                                             const std::string& publisher)
{
  for (const auto& session : sessions_)
    session->skipJointState(problem, publisher);
}

void JointCalibrationSession::flush()
{
  for (const auto& session : sessions_)
    session->flush();
}

void JointCalibrationSession::tick()
{
  for (const auto& session : sessions_)
    session->tick();
}

std::size_t JointCalibrationSession::writePendingPairs()
{
  std::size_t unwritten = 0;
  for (const auto& session : sessions_)
    unwritten += session->writePendingPairs();
  return unwritten;
}

AssistantMarker JointCalibrationSession::assistantMarker() const
{
  if (sessions_.size() == 1)
    return sessions_.front()->assistantMarker();
  AssistantMarker marker;
  marker.ready = true;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const AssistantMarker own = sessions_[k]->assistantMarker();
    marker.alarm = marker.alarm || own.alarm;
    marker.ready = marker.ready && own.ready;
    if (!own.text.empty())
      marker.text += (marker.text.empty() ? "" : "\n") + sources_[k].topic + ": " + own.text;
  }
  std::lock_guard<std::mutex> lock(monitor_mutex_);
  if (monitor_) {
    const AssistantMarker health = monitor_->marker();
    marker.alarm = marker.alarm || health.alarm;
    if (!health.text.empty())
      marker.text += (marker.text.empty() ? "" : "\n") + health.text;
  }
  return marker;
}

void JointCalibrationSession::monitorPair(const MotionPair& pair, std::size_t source)
{
  std::lock_guard<std::mutex> lock(monitor_mutex_);
  monitor_->addPair(pair, source);
}

void JointCalibrationSession::watchJointly(
    const std::vector<std::shared_ptr<const MotionModel>>& models, const std::string& origin)
{
  if (!monitor_)
    return;
  std::lock_guard<std::mutex> lock(monitor_mutex_);
  monitor_->watch(models, origin);
}

void JointCalibrationSession::watchSavedCalibrations()
{
  std::vector<std::shared_ptr<const MotionModel>> models;
  std::string origin;
  for (const auto& session : sessions_) {
    const auto [model, model_origin] = session->activeModel();
    if (!model || model_origin.rfind("nominal", 0) == 0)
      return;  // a source without a calibration of its own: nothing joint to watch
    models.push_back(model);
    if (origin.empty())
      origin = model_origin;
  }
  watchJointly(models, origin);
}

std::vector<SessionStatusReport> JointCalibrationSession::jointStatusReports() const
{
  std::vector<SessionStatusReport> statuses;
  std::lock_guard<std::mutex> lock(monitor_mutex_);
  if (monitor_ && monitor_->watching())
    monitor_->addStatuses(&statuses);
  return statuses;
}

std::optional<double> JointCalibrationSession::healthStatistic() const
{
  {
    std::lock_guard<std::mutex> lock(monitor_mutex_);
    if (monitor_)
      return monitor_->watching() ? std::optional<double>(monitor_->healthStatistic())
                                  : std::nullopt;
  }
  std::optional<double> largest;
  for (const auto& session : sessions_) {
    if (const std::optional<double> statistic = session->healthStatistic())
      largest = std::max(largest.value_or(*statistic), *statistic);
  }
  return largest;
}

JointCalibrateOutcome JointCalibrationSession::calibrate(const CalibrationRequest& request)
{
  if (sessions_.size() == 1)
    return {sessions_.front()->calibrate(request), std::nullopt, ""};
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  return calibrateJointly(request);
}

std::optional<std::vector<SessionFit>> JointCalibrationSession::fitSourcesAlone(
    const CalibrationRequest& request, std::size_t* pairs_collected, std::string* failure)
{
  std::vector<SessionFit> fits;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const CalibrateOutcome alone = sessions_[k]->calibrate(request);
    *pairs_collected += alone.pairs_collected;
    // As calibrate_bag: a fit alone that did not converge still gives the joint fit its start
    // (its table says so); a source without one stops the call.
    if (!alone.fit) {
      *failure = "source " + std::to_string(k) + " (" + sources_[k].topic + "): " + alone.message;
      return std::nullopt;
    }
    fits.push_back(*alone.fit);
  }
  return fits;
}

JointCalibrateOutcome JointCalibrationSession::calibrateJointly(const CalibrationRequest& request)
{
  JointCalibrateOutcome result;
  CalibrateOutcome& outcome = result.outcome;
  if ((!request.model.empty() && request.model != config_.model) || !request.options.empty()) {
    outcome.message =
        "with several ego-motion sources the fit is the joint fit of the "
        "configuration's model '" +
        config_.model + "' (no other model, no options)";
    return result;
  }
  std::string failure;
  const std::optional<std::vector<SessionFit>> fits =
      fitSourcesAlone(request, &outcome.pairs_collected, &failure);
  if (!fits) {
    outcome.message = "cannot fit the sources jointly: " + failure;
    return result;
  }
  std::vector<JointSourceInput> inputs;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const CalibrationJobResult& job = (*fits)[k].job;
    inputs.push_back({sources_[k].topic, sessions_[k]->sensorFrame(), job.pairs,
                      job.report.T_base_sensor, job.time_offset_s, (*fits)[k].fit_interval_s});
    names.push_back(sources_[k].topic);
  }
  try {
    result.joint = fitSourcesJointly(config_, inputs);
    result.text = formatJointFitReport(*result.joint, names);
  } catch (const std::exception& error) {
    outcome.message = "joint " + config_.model + " fit failed: " + error.what();
    return result;
  }
  SessionFit first = fits->front();
  first.job.report = sensorModelReport(*result.joint, 0);
  first.job.model = jointSensorModel(config_, *result.joint, 0);
  outcome.fit = first;
  if (!result.joint->converged) {
    outcome.message = "joint " + config_.model + " fit did not converge (" +
                      result.joint->termination + "); the active models are unchanged";
    return result;
  }
  outcome.message = adoptJointFit(*result.joint, *fits, &outcome.success);
  if (outcome.success) {
    joint_ = result.joint;
    joint_inputs_ = inputs;
    joint_text_ = result.text;
  }
  return result;
}

std::string JointCalibrationSession::adoptJointFit(const JointFitReport& joint,
                                                   const std::vector<SessionFit>& fits,
                                                   bool* success)
{
  std::string message =
      "joint " + config_.model + " fit of " + std::to_string(fits.size()) + " sensors:";
  for (const ParameterEstimate& parameter : joint.intrinsics) {
    char text[120];
    std::snprintf(text, sizeof(text), " %s %.6g", parameter.name.c_str(), parameter.value);
    message += text;
  }
  message += ".";
  *success = true;
  std::vector<std::shared_ptr<const MotionModel>> views;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    SessionFit view = fits[k];
    view.job.report = sensorModelReport(joint, k);
    view.job.model = jointSensorModel(config_, joint, k);
    views.push_back(view.job.model);
    const CalibrateOutcome adopted = sessions_[k]->adoptFit(view, view.job.pairs.size());
    *success = *success && adopted.success;
    message += " [" + sources_[k].topic + "] pose " + poseText(joint.sensors[k].T_base_sensor) +
               " from " + std::to_string(joint.sensors[k].pairs) + " pairs: " + adopted.message;
  }
  if (*success) {
    std::size_t pairs = 0;
    for (const JointSensorReport& sensor : joint.sensors)
      pairs += sensor.pairs;
    watchJointly(views, "joint fit of " + std::to_string(pairs) + " pairs");
  }
  return message;
}

std::pair<bool, std::string> JointCalibrationSession::save()
{
  if (sessions_.size() == 1)
    return sessions_.front()->save();
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  if (!joint_)
    return {false, "nothing to save: no successful joint ~calibrate since the node started"};
  if (options_.output_directory.empty())
    return {false, "nothing to save: the session has no output directory"};
  std::string message;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const auto [saved, text] = sessions_[k]->save();
    if (!saved)
      return {false, "source " + sources_[k].topic + ": " + text};
    message += "; " + text;
  }
  try {
    return {true, saveJoint() + message};
  } catch (const std::exception& error) {
    return {false, std::string("cannot save the joint fit: ") + error.what()};
  }
}

std::string JointCalibrationSession::saveJoint() const
{
  const std::string directory = options_.output_directory;
  fs::create_directories(directory);
  writeFileAtomically(directory + "/" + kResultFileName,
                      jointResultYaml(config_, *joint_, joint_inputs_, options_.source));
  std::string urdf;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    urdf += laserJointUrdf(joint_->sensors[k].T_base_sensor, options_.base_frame,
                           joint_inputs_[k].frame);
  }
  writeFileAtomically(directory + "/laser_joints.urdf", urdf);
  // No controller form for every model (tricycle): then no controller.yaml.
  const std::string controller = controllerYaml(sensorModelReport(*joint_, 0), options_.source);
  if (!controller.empty())
    writeFileAtomically(directory + "/controller.yaml", controller);
  writeFileAtomically(directory + "/joint_report.txt", joint_text_);
  return "saved the joint fit in " + fs::absolute(directory).lexically_normal().string() +
         " (result.yaml, laser_joints.urdf, " + (controller.empty() ? "" : "controller.yaml, ") +
         "joint_report.txt)";
}

std::pair<bool, std::string> JointCalibrationSession::reset()
{
  if (sessions_.size() == 1)
    return sessions_.front()->reset();
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  bool success = true;
  std::string message;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const auto [reset, text] = sessions_[k]->reset();
    success = success && reset;
    message += (k == 0 ? "" : "; ") + sources_[k].topic + ": " + text;
  }
  return {success, message};
}

}  // namespace odometry_calibration
