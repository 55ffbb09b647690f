// The live node's services: ~calibrate, ~save, ~reset.
#include <algorithm>
#include <ctime>
#include <filesystem>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/report/controller_yaml.h"
#include "odometry_calibration/ros/calibration_node.h"
#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/report_messages.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Local date and time for archived file names, e.g. 20261123-140312.
std::string wallClockTag()
{
  const std::time_t now = std::time(nullptr);
  char tag[32];
  std::strftime(tag, sizeof(tag), "%Y%m%d-%H%M%S", std::localtime(&now));
  return tag;
}

}  // namespace

// --- Services -------------------------------------------------------------------------------

bool CalibrationNode::onCalibrate(Calibrate::Request& request, Calibrate::Response& response)
{
  response.success = false;
  CalibrationConfig config;
  std::vector<MotionPair> pairs;
  std::vector<IntervalPairs> candidates;
  double time_offset_s = 0.0;
  std::string guidance;
  std::vector<EncoderSample> history;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    config = config_;
    pairs = pairs_;
    guidance = guidanceSummary();
    history = encoder_history_;
    if (candidates_)
      candidates = candidates_->pairs();
    time_offset_s = config_.collector.time_offset_s;
  }
  const std::string name = request.model.empty() ? config.model : request.model;
  try {
    requireKnownModel(name, "model");
  } catch (const std::invalid_argument& error) {
    response.message = error.what();
    return true;
  }
  try {
    // The model sections as this model needs them (its joints resolved and checked).
    config.models =
        configForModel(config_text_, name, request.options, options_.config_path).models;
  } catch (const std::exception& error) {
    response.message =
        "cannot fit " + name + " with this configuration and options: " + std::string(error.what());
    return true;
  }
  if (static_cast<int>(pairs.size()) < options_.min_pairs) {
    response.message = "only " + std::to_string(pairs.size()) + " pairs collected, " +
                       std::to_string(options_.min_pairs) +
                       " needed (~min_pairs): drive more, straight and turning both ways" +
                       guidance;
    return true;
  }
  // With keyframes.fit_intervals_s: the fit interval chosen by cross-validation on the
  // interval_s pairs (calibration/fit_interval.h); without, or when it cannot run, interval_s.
  double fit_interval_s = config.collector.keyframe_interval_s;
  std::vector<MotionPair> fit_pairs = pairs;
  std::string interval_text;
  if (!candidates.empty()) {
    candidates.push_back({config.collector.keyframe_interval_s, pairs});
    std::sort(
        candidates.begin(), candidates.end(),
        [](const IntervalPairs& a, const IntervalPairs& b) { return a.interval_s < b.interval_s; });
    CalibrationConfig choosing = config;
    choosing.model = name;
    try {
      const FitIntervalChoice choice = chooseFitInterval(choosing, candidates, pairs);
      for (IntervalPairs& candidate : candidates) {
        if (candidate.interval_s == choice.interval_s) {
          fit_interval_s = candidate.interval_s;
          fit_pairs = std::move(candidate.pairs);
        }
      }
      interval_text = formatFitIntervalChoice(choice, config.collector.keyframe_interval_s);
    } catch (const std::exception& error) {
      interval_text = "fit interval: kept keyframes.interval_s (" + std::string(error.what()) + ")";
    }
    if (!interval_text.empty() && interval_text.back() == '\n')
      interval_text.pop_back();
    ROS_INFO("%s", interval_text.c_str());
  }
  std::shared_ptr<MotionModel> model;
  ModelReport report;
  std::string offset_text;
  try {
    // The same job as calibrate_bag's, with the time-offset search on the encoder history the
    // node keeps when the configuration asks for it (estimate_time_offset); no report
    // trajectories.
    config.model = name;
    CalibrationJobOptions job_options;
    job_options.allow_time_offset = !history.empty();
    job_options.compare_trajectories = false;
    CalibrationJobResult job = runCalibrationJob(config, fit_pairs, history, job_options);
    model = job.model;
    report = std::move(job.report);
    time_offset_s = job.time_offset_s;
    offset_text = timeOffsetSentence(config, job, history.empty());
  } catch (const std::exception& error) {
    response.message = name + " fit failed: " + error.what();
    return true;
  }
  response.report = ros_conversions::toReportMsg(report, pairs.size(), time_offset_s);
  report_publisher_.publish(response.report);
  const std::string summary = formatModelReport(report);
  if (!report.converged) {
    response.message =
        name + " fit did not converge (" + report.termination + "); the active model is unchanged";
    ROS_WARN("%s\n%s", response.message.c_str(), summary.c_str());
    return true;
  }
  const std::string source = "live node " + ros::this_node::getName();
  const std::string result_yaml = calibrationResultYaml(report, *model, source, time_offset_s,
                                                        jointLayout(config).names, fit_interval_s);
  try {
    // Every fit is kept (last_fit.yaml); ~save makes it the calibration loaded on start.
    writeFileAtomically(options_.output_directory + "/last_fit.yaml", result_yaml);
  } catch (const std::exception& error) {
    ROS_ERROR("cannot write last_fit.yaml: %s", error.what());
  }
  // The corrected odometry is integrated again over the whole run with the new model, so that
  // ~odom and its path show the calibrated trajectory (one jump at the fit; see README).
  std::vector<EncoderSample> samples;
  Pose2 path_start;
  std::optional<Pose2> T_base_sensor;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    samples.assign(path_samples_.begin(), path_samples_.end());
    path_start = path_samples_start_;
    T_base_sensor =
        report.has_extrinsic ? std::optional<Pose2>(report.T_base_sensor) : T_base_sensor_;
  }
  auto replay = std::make_unique<OdometryIntegrator>(model, T_base_sensor, fit_interval_s);
  replay->setWindowCovarianceFloor(config.collector.covariance_floor.asDiagonal());
  replay->restartAt(path_start);
  std::vector<geometry_msgs::PoseStamped> path;
  auto add = [&](const EncoderSample& sample, bool to_path) {
    if (replay->add(sample) && to_path)
      path.push_back(
          ros_conversions::toPoseStampedMsg(replay->pose(), sample.stamp_s, options_.odom_frame));
  };
  try {
    for (const EncoderSample& sample : samples)
      add(sample, true);
    std::lock_guard<std::mutex> lock(state_mutex_);
    // What arrived while integrating, then the newest sample.
    for (const EncoderSample& sample : path_samples_)
      add(sample, true);
    if (corrected_odometry_ && corrected_odometry_->lastSample())
      add(*corrected_odometry_->lastSample(), false);
    T_base_sensor_ = T_base_sensor;
    fitted_model_ = model;
    fitted_result_yaml_ = result_yaml;
    fitted_controller_yaml_ = controllerYaml(report, source);
    corrected_odometry_ = std::move(replay);
    model_interval_s_ = fit_interval_s;
    corrected_path_.poses = std::move(path);
    active_model_ = model;
    active_model_origin_ = "fit of " + std::to_string(fit_pairs.size()) + " pairs";
    publishExtrinsic();
    applyTimeOffset(time_offset_s);
    startHealthMonitor(model);
    recentreGuidance(name, report);
  } catch (const std::exception& error) {
    response.message = name + " fitted, but its odometry failed: " + error.what() +
                       "; the active model is unchanged";
    return true;
  }
  response.success = true;
  response.message = name + " fitted to " + std::to_string(report.pairs_used) + " pairs (" +
                     std::to_string(report.outliers) + " rejected); residual RMS per pair " +
                     (report.before.count > 0 ? std::to_string(report.before.translation_m) + " -> "
                                              : std::string()) +
                     std::to_string(report.after.translation_m) +
                     " m. Now driving ~odom; call ~save to keep it.";
  if (!interval_text.empty())
    response.message += " " + interval_text + ".";
  response.message += offset_text;
  for (const std::string& warning : report.warnings)
    response.message += " WARNING: " + warning;
  response.message += guidance;
  if (report.warnings.empty())
    ROS_INFO("%s\n%s", response.message.c_str(), summary.c_str());
  else
    ROS_WARN("%s\n%s", response.message.c_str(), summary.c_str());
  return true;
}

bool CalibrationNode::onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!fitted_model_) {
    response.success = false;
    response.message = "nothing to save: no successful ~calibrate since the node started";
    return true;
  }
  const std::string result_path =
      fs::absolute(options_.output_directory + "/result.yaml").lexically_normal().string();
  try {
    writeFileAtomically(result_path, fitted_result_yaml_);
    response.message = "saved " + result_path;
    const std::string controller_path =
        fs::absolute(options_.output_directory + "/controller.yaml").lexically_normal().string();
    if (!fitted_controller_yaml_.empty()) {
      writeFileAtomically(controller_path, fitted_controller_yaml_);
      response.message += ", " + controller_path;
    } else {  // an earlier calibration's controller values must not pass for this one's
      std::error_code ignored;
      fs::remove(controller_path, ignored);
    }
    if (T_base_sensor_) {
      const std::string urdf_path =
          fs::absolute(options_.output_directory + "/laser_joint.urdf").lexically_normal().string();
      writeFileAtomically(urdf_path,
                          laserJointUrdf(*T_base_sensor_, options_.base_frame, sensorFrame()));
      response.message += " and " + urdf_path;
    }
    response.success = true;
  } catch (const std::exception& error) {
    response.success = false;
    response.message = std::string("cannot save: ") + error.what();
  }
  ROS_INFO("%s", response.message.c_str());
  return true;
}

bool CalibrationNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  const std::size_t dropped = pairs_.size();
  collector_->reset();
  if (candidates_)
    candidates_->clear();
  appender_.reset();
  const std::string pairs_path = options_.output_directory + "/pairs.csv";
  std::string archived;
  if (fs::exists(pairs_path) && dropped > 0)
    archived = archivePairsFile("~reset");
  else
    fs::remove(pairs_path);  // only a header: nothing to keep
  pairs_.clear();
  pairs_resumed_ = 0;
  pairs_unwritten_ = 0;
  try {
    appender_ = std::make_unique<PairsCsvAppender>(pairs_path, jointLayout(config_));
    pairs_file_problem_.clear();
  } catch (const std::exception& error) {
    // New pairs stay in memory until the file can be created (writePendingPairs()).
    ROS_ERROR("%s: new pairs stay in memory until it can be written", error.what());
    pairs_file_problem_ = error.what();
  }
  restartOdometry();
  resetAssistant();
  response.success = true;
  response.message = "collection restarted: " + std::to_string(dropped) + " pairs set aside" +
                     (archived.empty() ? std::string() : " in " + archived) +
                     "; the active model is kept";
  ROS_INFO("%s", response.message.c_str());
  return true;
}

std::string CalibrationNode::archivePairsFile(const std::string& why)
{
  const std::string pairs_path = options_.output_directory + "/pairs.csv";
  std::string archived = options_.output_directory + "/pairs-" + wallClockTag() + ".csv";
  for (int i = 1; fs::exists(archived); ++i)
    archived =
        options_.output_directory + "/pairs-" + wallClockTag() + "-" + std::to_string(i) + ".csv";
  fs::rename(pairs_path, archived);
  ROS_WARN("moved %s to %s (%s)", pairs_path.c_str(), archived.c_str(), why.c_str());
  return archived;
}

}  // namespace odometry_calibration
