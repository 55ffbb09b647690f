#include "odometry_calibration/session/calibration_session.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/calibration/saved_calibration_score.h"

namespace odometry_calibration {

std::string scanRaysProblem(std::size_t rays, long long max_rays)
{
  if (static_cast<long long>(rays) <= max_rays)
    return "";
  return "a scan of " + std::to_string(rays) +
         " rays, more than ego_motion.max_scan_rays = " + std::to_string(max_rays) +
         " (raise it for a laser with more rays)";
}
namespace {

namespace fs = std::filesystem;

/// Assumed per-keyframe-interval covariance of the uncalibrated (nominal) odometry: 1 cm, 1 cm,
/// 0.01 rad [m^2, m^2, rad^2].
const Eigen::Matrix3d kNominalWindowCovariance = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();

double steadySeconds()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

CalibrationSession::CalibrationSession(const CalibrationConfig& config,
                                       const std::string& config_text,
                                       const std::string& config_source, SessionOptions options,
                                       SessionListener listener)
    : config_(config),
      config_text_(config_text),
      config_source_(config_source),
      options_(std::move(options)),
      listener_(std::move(listener)),
      channels_(encoderChannels(config_))
{
  if (!options_.wall_clock)
    options_.wall_clock = steadySeconds;
  if (options_.min_pairs < 1)
    throw std::invalid_argument("min_pairs must be >= 1, got " +
                                std::to_string(options_.min_pairs));
  model_interval_s_ = config_.collector.keyframe_interval_s;
  keep_history_ = options_.keep_encoder_history.value_or(config_.estimate_time_offset);
  candidate_intervals_s_ = options_.candidate_intervals_s.value_or(config_.fit_intervals_s);
  inputs_ = std::make_unique<InputMonitor>(options_.topics, options_.silent_topic_timeout_s, now());
  publishers_ = std::make_unique<InputPublishers>(
      options_.topics,
      std::array<std::string, 2>{config_.joint_state_publisher, config_.ego_motion_publisher},
      std::array<std::string, 2>{"joint_state_publisher", config_.ego_motion_publisher_key});
  encoder_watch_ = std::make_unique<EncoderWatch>(channels_);
  if (!options_.output_directory.empty())
    fs::create_directories(options_.output_directory);
  if (options_.load_saved_calibration && !options_.output_directory.empty())
    loadSavedCalibration();
  makeCollectors();
  if (config_.estimate_time_offset) {  // to pair again at the estimated offset
    try {
      record_ = std::make_unique<InputRecord>(options_.output_directory);
    } catch (const std::exception& error) {
      dropRecord(error.what());  // the session runs on, pairing only at the configured offset
    }
  }
  store_ = std::make_unique<PairsStore>(options_.output_directory, jointLayout(config_),
                                        options_.resume_pairs, options_.log);
  if (options_.odometry)
    startOdometry();
  if (options_.assistant) {
    assistant_ = std::make_unique<SessionAssistant>(options_.assistant_options, config_,
                                                    config_text_, config_source_, options_.log);
    for (const MotionPair& pair : store_->pairs())
      assistant_->addPair(pair);
    if (active_model_ && active_model_origin_.rfind("nominal", 0) != 0)
      assistant_->watch(active_model_, active_model_origin_);
  }
}

CalibrationSession::~CalibrationSession() = default;

double CalibrationSession::now() const
{
  return options_.wall_clock();
}

void CalibrationSession::say(SessionLogLevel level, const std::string& text) const
{
  if (options_.log)
    options_.log(level, text);
}

void CalibrationSession::loadSavedCalibration()
{
  // The last saved calibration: its model drives the corrected odometry, its time offset the
  // pairing, its sensor pose the static transform.
  const std::string result_path = options_.output_directory + "/result.yaml";
  if (!fs::exists(result_path))
    return;
  try {
    const CalibrationResult saved = readCalibrationResult(result_path);
    // Another robot's (or configuration's) result: its joints (when recorded) must be these,
    // and its model must take them.
    requireCalibrationJoints(saved.joints, jointLayout(config_).names, "the configuration");
    const auto joints = static_cast<Eigen::Index>(channels_.size());
    saved.model->predict(
        {{0.0, Eigen::VectorXd::Zero(joints)}, {0.1, Eigen::VectorXd::Zero(joints)}});
    active_model_ = saved.model;
    active_model_origin_ = "saved " + result_path;
    if (saved.has_extrinsic)
      T_base_sensor_ = saved.T_base_sensor;
    config_.collector.time_offset_s = saved.time_offset_s;
    if (saved.fit_interval_s > 0.0)
      model_interval_s_ = saved.fit_interval_s;
    char text[300];
    std::snprintf(text, sizeof(text), " (model %s, time offset %.3f s)",
                  saved.model->name().c_str(), saved.time_offset_s);
    say(SessionLogLevel::kInfo, "loaded the saved calibration " + result_path + text);
  } catch (const std::exception& error) {
    say(SessionLogLevel::kError, "cannot use the saved calibration (" + std::string(error.what()) +
                                     "): starting from the nominal model");
  }
}

void CalibrationSession::makeCollectors()
{
  buildCollectors(config_.collector, &collector_, &candidates_);
}

void CalibrationSession::buildCollectors(const CollectorOptions& options,
                                         std::unique_ptr<PairCollector>* collector,
                                         std::unique_ptr<CandidateCollectors>* candidates) const
{
  *collector = std::make_unique<PairCollector>(channels_, options, priorPredictor(config_));
  std::vector<double> other_intervals;
  for (const double interval : candidate_intervals_s_) {
    if (std::abs(interval - options.keyframe_interval_s) > 1e-9)
      other_intervals.push_back(interval);
  }
  candidates->reset();
  if (!other_intervals.empty()) {
    *candidates = std::make_unique<CandidateCollectors>(channels_, options, priorPredictor(config_),
                                                        other_intervals);
  }
}

void CalibrationSession::startOdometry()
{
  odometry_ = std::make_unique<SessionOdometry>(channels_, options_.odometry_options);
  // The nominal robot (the prior model at its start values) drives the nominal odometry, and
  // the corrected one until a calibration is fitted or loaded.
  if (std::shared_ptr<MotionModel> nominal = priorModel(config_)) {
    has_nominal_ = true;
    odometry_->setNominal(std::make_unique<OdometryIntegrator>(
        nominal, priorSensorPose(config_), config_.collector.keyframe_interval_s));
    if (!active_model_) {
      active_model_ = nominal;
      active_model_origin_ = "nominal " + nominal->name() + " (configuration's start values)";
      T_base_sensor_.reset();
    }
  }
  if (!active_model_) {
    say(SessionLogLevel::kWarn,
        "no odometry until the first ~calibrate: prior_model is 'none' and there is no saved "
        "calibration");
    return;
  }
  const bool nominal = !T_base_sensor_ && active_model_origin_.rfind("nominal", 0) == 0;
  auto corrected = std::make_unique<OdometryIntegrator>(
      active_model_, nominal ? priorSensorPose(config_) : T_base_sensor_,
      nominal ? config_.collector.keyframe_interval_s : model_interval_s_);
  // The nominal robot reports no uncertainty of its own: assume 1 cm and 0.01 rad per keyframe
  // interval until a fit replaces it with the residual spread.
  if (nominal)
    corrected->setWindowCovarianceFloor(kNominalWindowCovariance);
  odometry_->setCorrected(std::move(corrected));
}

// --- Queries --------------------------------------------------------------------------------

std::vector<MotionPair> CalibrationSession::pairs() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return store_->pairs();
}

std::vector<IntervalPairs> CalibrationSession::candidatePairs() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return candidates_ ? candidates_->pairs() : std::vector<IntervalPairs>{};
}

std::vector<EncoderSample> CalibrationSession::encoderHistory() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return encoder_history_;
}

std::string CalibrationSession::publisherConflict() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return publishers_->conflict();
}

std::string CalibrationSession::inputConflict() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string publishers = publishers_->conflict();
  return publishers.empty() ? counts_.configuration_conflict : publishers;
}

SessionCounts CalibrationSession::counts() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  SessionCounts counts = counts_;
  counts.statistics = collector_->statistics();
  counts.pairs = store_->pairs().size();
  counts.pairs_resumed = store_->resumed();
  counts.pairs_unwritten = store_->unwritten();
  counts.encoder_messages = inputs_->messages(SessionInput::kEncoders);
  counts.ego_messages = inputs_->messages(SessionInput::kEgoMotion);
  counts.publisher_conflict = publishers_->conflict();
  counts.ignored_encoder_messages = publishers_->ignored(SessionInput::kEncoders);
  counts.ignored_ego_messages = publishers_->ignored(SessionInput::kEgoMotion);
  counts.encoder_publisher = publishers_->publisher(SessionInput::kEncoders);
  counts.ignored_encoder_publisher = publishers_->otherPublisher(SessionInput::kEncoders);
  counts.ego_publisher = publishers_->publisher(SessionInput::kEgoMotion);
  counts.ignored_ego_publisher = publishers_->otherPublisher(SessionInput::kEgoMotion);
  return counts;
}

double CalibrationSession::timeOffset() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return config_.collector.time_offset_s;
}

std::optional<Pose2> CalibrationSession::sensorPose() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return T_base_sensor_;
}

std::string CalibrationSession::sensorFrame() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return sensor_frame_.empty() ? options_.default_sensor_frame : sensor_frame_;
}

bool CalibrationSession::hasNominalOdometry() const
{
  return has_nominal_;
}

OdometryPaths CalibrationSession::paths() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!odometry_)
    return {};
  // The scan-matched sensor poses drawn as base_link poses through the current sensor pose (or
  // the configured one), so the three paths overlay.
  return odometry_->paths(T_base_sensor_ ? *T_base_sensor_
                                         : priorSensorPose(config_).value_or(Pose2()));
}

AssistantMarker CalibrationSession::assistantMarker() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return assistant_ ? assistant_->marker() : AssistantMarker{};
}

std::optional<double> CalibrationSession::healthStatistic() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!assistant_ || !assistant_->watching())
    return std::nullopt;
  return assistant_->healthStatistic();
}

std::pair<std::shared_ptr<const MotionModel>, std::string> CalibrationSession::activeModel() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return {active_model_, active_model_origin_};
}

}  // namespace odometry_calibration
