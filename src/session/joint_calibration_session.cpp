#include "odometry_calibration/session/joint_calibration_session.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/eval/joint_fit_text.h"
#include "odometry_calibration/report/calibration_files.h"
#include "odometry_calibration/scan/pcl_support.h"

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

/// Throws std::invalid_argument naming the first of a call's `options` that a joint fit of
/// `model` does not take: another section than the model's own (the model is the request's),
/// or its sensor_pose (each source starts from its own, ego_motion.sources[].sensor_pose).
void refuseNonJointOptions(const std::string& model, const std::string& options)
{
  if (options.empty())
    return;
  YAML::Node root;
  try {
    root = YAML::Load(options);
  } catch (const YAML::Exception& error) {
    throw std::invalid_argument(std::string("the options are not YAML: ") + error.what());
  }
  try {
    refuseYamlBeyond(root, "the options");
  } catch (const std::runtime_error& error) {
    throw std::invalid_argument(error.what());
  }
  if (root.IsNull())
    return;
  if (!root.IsMap())
    throw std::invalid_argument("the options must be a YAML mapping, e.g. \"{" + model +
                                ": {huber_threshold: 2}}\"");
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key != model) {
      throw std::invalid_argument("option '" + key + "' does not apply to the joint " + model +
                                  " fit of several sources (it takes only " + model +
                                  ".* options; the model is the request's model)");
    }
    if (entry.second.IsMap() && entry.second["sensor_pose"]) {
      throw std::invalid_argument("option '" + model +
                                  ".sensor_pose' does not apply to the joint fit: each source "
                                  "starts from its own (ego_motion.sources[].sensor_pose)");
    }
  }
}

/// A build without PCL cannot turn clouds into scans: a cloud source is refused up front (not
/// every message skipped), naming its key and topic. A runtime_error: the bag tools report it as
/// it is (an invalid_argument there is taken for a corrupted bag's).
void refuseCloudsWithoutPcl(const CalibrationConfig& config)
{
  if constexpr (kHavePcl)
    return;
  const std::vector<EgoMotionSourceConfig> sources = egoMotionSources(config);
  for (std::size_t k = 0; k < sources.size(); ++k) {
    if (sources[k].type != EgoMotionSource::kCloud)
      continue;
    const std::string key = config.ego_motion_sources.empty()
                                ? "ego_motion.source"
                                : "ego_motion.sources[" + std::to_string(k) + "].type";
    throw std::runtime_error(
        withoutPclMessage(key + ": cloud (sensor_msgs/PointCloud2 on '" + sources[k].topic + "')"));
  }
}

}  // namespace

JointCalibrationSession::JointCalibrationSession(
    const CalibrationConfig& config, const std::string& config_text,
    const std::string& config_source, const SessionOptions& options,
    const std::function<SessionListener(std::size_t)>& listener, JointFitFunction fit_jointly)
    : config_(config),
      config_text_(config_text),
      config_source_(config_source),
      wheel_signals_(std::make_unique<WheelSignals>(config)),
      options_(options),
      sources_(egoMotionSources(config)),
      fit_jointly_(std::move(fit_jointly))
{
  refuseCloudsWithoutPcl(config);
  if (config.wheels.source == WheelSource::kTicks) {
    wheel_watch_ = std::make_unique<WheelTopicWatch>(config.wheels.topics,
                                                     options.silent_topic_timeout_s, wallNow());
  }
  if (!config.gyro.topic.empty()) {
    gyro_ = std::make_unique<GyroSource>(config.gyro, config.time_offset_search_min_s,
                                         config.time_offset_search_max_s);
    if (options.assistant && options.assistant_options.health_monitor)
      gyro_health_ = std::make_unique<GyroHealth>(options.log);
    if (config.gyro.odom_heading && options.odometry)
      gyro_heading_ = std::make_unique<GyroHeadingOdometry>(config.gyro.max_gap_s);
  }
  if (sources_.size() <= 1) {  // one source: its session exactly as before
    const SessionListener own_listener = withGyro(listener ? listener(0) : SessionListener{});
    sessions_.push_back(std::make_unique<CalibrationSession>(config, config_text, config_source,
                                                             options, own_listener));
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
    if (k == 0)
      own_listener = withGyro(std::move(own_listener));
    sessions_.push_back(std::make_unique<CalibrationSession>(
        configForSource(config, k), config_text, config_source, own, own_listener));
  }
  watchSavedCalibrations();
}

JointCalibrationSession::~JointCalibrationSession() = default;

std::string JointCalibrationSession::startSummary() const
{
  std::string ego_topics = options_.topics[1];
  if (sourceCount() > 1) {
    ego_topics.clear();
    for (std::size_t k = 0; k < sourceCount(); ++k)
      ego_topics += (k == 0 ? "" : ", ") + sourceConfig(k).topic;
    ego_topics += " (fitted jointly)";
  }
  char numbers[160];
  std::snprintf(numbers, sizeof(numbers), "keyframes every %.2f s, time offset %.3f s",
                config_.collector.keyframe_interval_s, sessions_.front()->timeOffset());
  return "collecting pairs: " + wheelInputName(config_.wheels, config_.joint_state_topic) +
         ", ego-motion on " + ego_topics + ", " + numbers + "; output in " +
         options_.output_directory;
}

void JointCalibrationSession::flush()
{
  for (const auto& session : sessions_)
    session->flush();
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
  if (gyro_health_) {
    if (std::optional<SessionStatusReport> gyro = gyro_health_->status())
      statuses.push_back(std::move(*gyro));
  }
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
  JointCalibrateOutcome result;
  if (sessions_.size() == 1) {
    result.outcome = sessions_.front()->calibrate(request);
  } else {
    std::lock_guard<std::mutex> fitting(fit_mutex_);
    result = calibrateJointly(request);
  }
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  fitGyro(&result);
  return result;
}

CalibrationConfig JointCalibrationSession::jointModelConfig(const std::string& name,
                                                            const std::string& options) const
{
  refuseNonJointOptions(name, options);
  CalibrationConfig config = config_;
  if (name != config_.model || !options.empty())
    config.models = configForModel(config_text_, name, options, config_source_).models;
  config.model = name;
  return config;
}

std::optional<std::vector<SessionFit>> JointCalibrationSession::fitSourcesAlone(
    const CalibrationRequest& request, const CalibrationConfig& joint_config,
    std::size_t* pairs_collected, std::string* failure)
{
  std::vector<SessionFit> fits;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    CalibrationRequest own = request;  // the joint model, from this source's start pose
    own.model = joint_config.model;
    own.options.clear();
    own.reply_holdout_fraction = 0.0;  // the joint fit replies, without a held-out table
    own.models = configForSource(joint_config, k).models;
    const CalibrateOutcome alone = sessions_[k]->calibrate(own);
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
  const std::string name = request.model.empty() ? config_.model : request.model;
  if (const std::string problem = jointFitModelProblem(name); !problem.empty()) {
    outcome.message = "cannot fit " + name + " jointly: " + problem;
    return result;
  }
  CalibrationConfig joint_config;
  try {
    joint_config = jointModelConfig(name, request.options);
  } catch (const std::exception& error) {
    outcome.message = "cannot fit " + name + " jointly " +
                      (request.options.empty() ? std::string("with the configuration")
                                               : "with the options " + request.options) +
                      ": " + error.what();
    return result;
  }
  std::string failure;
  std::optional<std::vector<SessionFit>> fits =
      fitSourcesAlone(request, joint_config, &outcome.pairs_collected, &failure);
  if (!fits) {
    outcome.message = "cannot fit the sources jointly: " + failure;
    return result;
  }
  result.alone = std::move(*fits);
  if (!fitJointly(joint_config, &result))
    return result;
  if (!result.joint->converged) {
    outcome.message = "joint " + name + " fit did not converge (" + result.joint->termination +
                      "); the active models are unchanged";
    return result;
  }
  if (options_.adopt_fits) {
    outcome.message = adoptJointFit(joint_config, *result.joint, result.alone, &outcome.success);
  } else {  // calibrate_bag: the fit is the result, no source's session runs on with it
    outcome.success = true;
    outcome.message =
        "joint " + name + " fit of " + std::to_string(sessions_.size()) + " sensors converged";
  }
  if (outcome.success) {
    joint_ = result.joint;
    joint_config_ = joint_config;
    joint_inputs_ = result.inputs;
    joint_text_ = result.text;
  }
  return result;
}

bool JointCalibrationSession::fitJointly(const CalibrationConfig& joint_config,
                                         JointCalibrateOutcome* result)
{
  std::vector<std::string> names;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const SessionFit& fit = result->alone[k];
    result->inputs.push_back({sources_[k].topic, sessions_[k]->sensorFrame(), fit.job.pairs,
                              fit.job.report.T_base_sensor, fit.job.time_offset_s,
                              fit.fit_interval_s});
    names.push_back(sources_[k].topic);
  }
  SessionFit first = result->alone.front();
  try {  // (a view's model checks its values: a diverged solve is a failed fit, not a throw)
    result->joint = fit_jointly_(joint_config, result->inputs);
    result->text = formatJointFitReport(*result->joint, names);
    first.job.report = sensorModelReport(*result->joint, 0);
    first.job.model = jointSensorModel(joint_config, *result->joint, 0);
  } catch (const std::exception& error) {
    result->joint.reset();
    result->joint_failure = error.what();
    result->outcome.message = "joint " + joint_config.model + " fit failed: " + error.what();
    return false;
  }
  result->outcome.fit = first;
  return true;
}

std::string JointCalibrationSession::adoptJointFit(const CalibrationConfig& joint_config,
                                                   const JointFitReport& joint,
                                                   const std::vector<SessionFit>& fits,
                                                   bool* success)
{
  const std::string model = joint_config.model;
  const auto notAdopted = [&](std::size_t k, const std::string& why) {
    return "joint " + model + " fit not adopted: source " + std::to_string(k) + " (" +
           sources_[k].topic + "): " + why +
           "; the previous calibration stays active in every source";
  };
  std::vector<SessionFit> views;
  std::vector<PreparedAdoption> prepared;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    views.push_back(fits[k]);
    try {  // everything that can fail, in every source, before any changes
      views[k].job.report = sensorModelReport(joint, k);
      views[k].job.model = jointSensorModel(joint_config, joint, k);
      prepared.push_back(
          sessions_[k]->prepareAdoption(views[k], model, configForSource(joint_config, k).models));
    } catch (const std::exception& error) {
      return notAdopted(k, error.what());
    }
  }
  std::size_t committed = 0;
  try {
    for (; committed < sessions_.size(); ++committed)
      sessions_[committed]->commitAdoption(prepared[committed]);
  } catch (const std::exception& error) {
    for (std::size_t k = committed; k-- > 0;)
      sessions_[k]->rollBackAdoption(prepared[k]);
    return notAdopted(committed, error.what());
  }
  std::string message = "joint " + model + " fit of " + std::to_string(fits.size()) + " sensors:";
  for (const ParameterEstimate& parameter : joint.intrinsics) {
    char text[120];
    std::snprintf(text, sizeof(text), " %s %.6g", parameter.name.c_str(), parameter.value);
    message += text;
  }
  message += ".";
  std::vector<std::shared_ptr<const MotionModel>> models;
  std::size_t pairs = 0;
  for (std::size_t k = 0; k < sessions_.size(); ++k) {
    const CalibrateOutcome adopted =
        sessions_[k]->finishAdoption(prepared[k], views[k].job.pairs.size());
    models.push_back(views[k].job.model);
    pairs += joint.sensors[k].pairs;
    message += " [" + sources_[k].topic + "] pose " + poseText(joint.sensors[k].T_base_sensor) +
               " from " + std::to_string(joint.sensors[k].pairs) + " pairs: " + adopted.message;
  }
  *success = true;
  watchJointly(models, "joint fit of " + std::to_string(pairs) + " pairs");
  return message;
}

std::pair<bool, std::string> JointCalibrationSession::save()
{
  std::lock_guard<std::mutex> fitting(fit_mutex_);
  if (sessions_.size() == 1)
    return gyro_fit_ ? saveWithGyro() : sessions_.front()->save();
  if (!joint_)
    return {false, "nothing to save: no successful joint ~calibrate since the node started"};
  if (options_.output_directory.empty())
    return {false, "nothing to save: the session has no output directory"};
  try {
    return {true, saveJoint()};
  } catch (const std::exception& error) {
    return {false,
            std::string("cannot save the joint fit, the previous files are kept: ") + error.what()};
  }
}

std::string JointCalibrationSession::saveJoint() const
{
  FileSet set;
  for (std::size_t k = 0; k < sessions_.size(); ++k)
    set.addUnder("source_" + std::to_string(k), sessions_[k]->filesToSave());
  const FileSet joint = jointCalibrationFiles(joint_config_, *joint_, joint_inputs_,
                                              options_.source, options_.base_frame, joint_text_);
  set.written.insert(set.written.end(), joint.written.begin(), joint.written.end());
  set.removed.insert(set.removed.end(), joint.removed.begin(), joint.removed.end());
  if (gyro_fit_)
    appendGyroResult(&set, *gyro_fit_, config_.gyro.topic);
  writeFileSet(options_.output_directory, set);
  std::string list;
  for (const auto& [name, content] : set.written)
    list += (list.empty() ? "" : ", ") + name;
  return "saved the joint fit in " +
         fs::absolute(options_.output_directory).lexically_normal().string() + ": " + list;
}

std::pair<bool, std::string> JointCalibrationSession::reset()
{
  if (gyro_)
    gyro_->clear();
  if (gyro_health_)
    gyro_health_->clear();
  if (gyro_heading_)
    gyro_heading_->reset();
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
