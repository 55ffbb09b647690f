// The session's inputs: encoder readings and ego-motion samples into the pair collectors, the
// encoder history and the odometry; each bad input counted and warned about.
#include <cmath>
#include <cstdio>

#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

/// The first restarts (time going backwards) kept in words; the count goes on.
constexpr std::size_t kRestartsKept = 100;

}  // namespace

void CalibrationSession::warnInput(const std::string& problem, const std::string& text)
{
  if (inputs_->mayWarn(problem, now()))
    say(SessionLogLevel::kWarn, text);
}

std::string CalibrationSession::oneStampProblem() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::pair<SessionInput, const InputStamps*> inputs[] = {
      {SessionInput::kEncoders, &counts_.encoder_stamps},
      {SessionInput::kEgoMotion, &counts_.ego_stamps}};
  for (const auto& [input, stamps] : inputs) {
    if (!stamps->oneStamp())
      continue;
    const bool encoders = input == SessionInput::kEncoders;
    const bool odometry = config_.wheels.source == WheelSource::kOdometry;
    const std::string type =
        encoders ? (odometry ? "base odometry" : "JointState") : egoMessageType(config_.ego_motion);
    // The configured topic (the input monitor's name for it may be a description).
    const std::string topic =
        encoders ? (config_.wheels.topics.empty() ? config_.joint_state_topic
                                                  : config_.wheels.topics.front())
        : config_.ego_motion == EgoMotionSource::kScan ? config_.scan_topic
                                                       : config_.ego_motion_topic;
    char stamp[32];
    std::snprintf(stamp, sizeof(stamp), "%.9g", stamps->first_s);
    return "all " + std::to_string(stamps->count) + " " + type + " samples on " + topic +
           " carry the same stamp " + stamp +
           " s: the publisher does not stamp its messages (header.stamp); stamp each with the "
           "time of its measurement";
  }
  return "";
}

void CalibrationSession::rejectInput(SessionInput input, const std::string& what,
                                     const std::string& problem)
{
  const bool encoders = input == SessionInput::kEncoders;
  std::size_t& count = encoders ? counts_.bad_encoder_messages : counts_.bad_ego_messages;
  if (count++ == 0)
    (encoders ? counts_.first_bad_encoder_message : counts_.first_bad_ego_message) = problem;
  last_problem_ = what + " skipped: " + problem;
  warnInput(problem, what + " on " + inputs_->topic(input) + " skipped (" + std::to_string(count) +
                         " so far): " + problem);
}

bool CalibrationSession::admit(SessionInput input, const std::string& publisher, bool carries_data)
{
  inputs_->received(input, now());
  const bool had_conflict = !publishers_->conflict().empty();
  const PublisherVerdict verdict = publishers_->check(input, publisher, carries_data);
  if (verdict == PublisherVerdict::kUse)
    return true;
  if (verdict == PublisherVerdict::kConflict) {
    if (!had_conflict) {
      last_problem_ = publishers_->conflict();
      say(SessionLogLevel::kError, publishers_->conflict());
    }
    return false;
  }
  const std::size_t ignored = publishers_->ignored(input);
  const std::string& chosen = input == SessionInput::kEncoders ? config_.joint_state_publisher
                                                               : config_.ego_motion_publisher;
  if (ignored == 1 || ignored % 1000 == 0) {
    say(SessionLogLevel::kWarn, "ignoring " + inputs_->topic(input) + " from " +
                                    publisherName(publisher) + " (" + publishers_->key(input) +
                                    ": " + publisherName(chosen) + "; " + std::to_string(ignored) +
                                    " ignored so far)");
  }
  return false;
}

void CalibrationSession::addJointPositions(double stamp_s, const Eigen::VectorXd& raw,
                                           const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!admit(SessionInput::kEncoders, publisher))
    return;
  counts_.encoder_stamps.add(stamp_s);
  encoder_watch_->add(raw);
  Eigen::VectorXd accepted;
  std::vector<CollectorEvent> events;
  record([&](InputRecord& inputs) { inputs.addEncoders(stamp_s, raw); });
  try {
    events = collector_->addEncoders(stamp_s, raw, &accepted);
    if (candidates_)
      candidates_->addEncoders(stamp_s, raw);
  } catch (const std::invalid_argument& error) {
    rejectInput(SessionInput::kEncoders, "JointState", error.what());
    return;
  }
  handleEvents(events, stamp_s);
  if (counts_.configuration_conflict.empty()) {
    counts_.configuration_conflict = collector_->configurationConflict();
    if (!counts_.configuration_conflict.empty())
      say(SessionLogLevel::kError, counts_.configuration_conflict);
  }
  if (accepted.size() == 0)  // an encoder glitch: not motion
    return;
  recordEncoderHistory(stamp_s, accepted);
  integrate(stamp_s, accepted);
}

void CalibrationSession::skipJointState(const std::string& problem, const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!admit(SessionInput::kEncoders, publisher, false))
    return;
  rejectInput(SessionInput::kEncoders, "JointState", problem);
}

void CalibrationSession::recordEncoderHistory(double stamp_s, const Eigen::VectorXd& accepted)
{
  if (!keep_history_ || history_broken_)
    return;
  if (!history_decoder_)
    history_decoder_ = std::make_unique<EncoderDecoder>(channels_);
  if (!encoder_history_.empty() && !(stamp_s > encoder_history_.back().stamp_s))
    return;  // a repeated stamp adds nothing (time going backwards broke the history already)
  encoder_history_.push_back({stamp_s, history_decoder_->decode(accepted)});
}

void CalibrationSession::integrate(double stamp_s, const Eigen::VectorXd& accepted)
{
  if (!odometry_)
    return;
  std::optional<OdometryState> state;
  try {
    state = odometry_->add(stamp_s, accepted, config_.collector.time_offset_s);
  } catch (const std::exception& error) {
    warnInput("odometry prediction failed",
              std::string("odometry prediction failed: ") + error.what());
    return;
  }
  if (state && listener_.odometry)
    listener_.odometry(*state);
}

std::vector<CollectorEvent> CalibrationSession::takeScan(double stamp_s, const Scan& scan)
{
  if (const std::string problem = scanRaysProblem(scan.ranges_m.size(), config_.max_scan_rays);
      !problem.empty())
    throw std::invalid_argument(problem);
  const std::size_t usable = countUsableReadings(scan);
  if (static_cast<int>(usable) < config_.collector.plicp.min_points) {
    throw std::invalid_argument(
        "only " + std::to_string(usable) + " of " + std::to_string(scan.ranges_m.size()) +
        " ranges are usable (the rest NaN, inf or outside [range_min, range_max]); matching "
        "needs scan_matching.min_points = " +
        std::to_string(config_.collector.plicp.min_points));
  }
  record([&](InputRecord& inputs) { inputs.addScan(stamp_s, scan); });
  std::vector<CollectorEvent> events = collector_->addScan(stamp_s, scan);
  if (candidates_)
    candidates_->addScan(stamp_s, scan);
  return events;
}

void CalibrationSession::noteFrame(const std::string& frame)
{
  if (frame.empty() || frame == sensor_frame_)
    return;
  if (!sensor_frame_.empty())
    say(SessionLogLevel::kWarn,
        "the sensor's frame changed from '" + sensor_frame_ + "' to '" + frame + "'");
  sensor_frame_ = frame;
  notifySensorPose();
}

void CalibrationSession::notifySensorPose() const
{
  if (listener_.sensor_pose)
    listener_.sensor_pose(T_base_sensor_,
                          sensor_frame_.empty() ? options_.default_sensor_frame : sensor_frame_);
}

void CalibrationSession::addScan(double stamp_s, const Scan& scan, const std::string& frame,
                                 const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!admit(SessionInput::kEgoMotion, publisher))
    return;
  counts_.ego_stamps.add(stamp_s);
  noteFrame(frame);
  std::vector<CollectorEvent> events;
  try {
    events = takeScan(stamp_s, scan);
  } catch (const std::invalid_argument& error) {
    rejectInput(SessionInput::kEgoMotion, "LaserScan", error.what());
    return;
  }
  handleEvents(events, stamp_s);
}

void CalibrationSession::addCloudScan(double stamp_s, const Scan& scan, const std::string& frame,
                                      const std::string& time_problem, const std::string& publisher)
{
  std::unique_lock<std::mutex> lock(mutex_);
  std::string problem;
  if (frame.empty()) {
    problem = "PointCloud2 names no frame (header.frame_id is empty)";
  } else if (cloud_frame_fixed_ && frame != sensor_frame_) {
    problem = "PointCloud2 in frame '" + frame + "', not the sensor's frame '" + sensor_frame_ +
              "' (the first cloud's)";
  }
  if (!problem.empty()) {
    lock.unlock();
    return skipEgoMessage("PointCloud2", problem, publisher);
  }
  if (!admit(SessionInput::kEgoMotion, publisher))
    return;
  cloud_frame_fixed_ = true;
  counts_.ego_stamps.add(stamp_s);
  noteFrame(frame);
  if (!time_problem.empty()) {
    if (counts_.clouds_without_times++ == 0)
      counts_.first_cloud_time_problem = time_problem;
    last_problem_ = "PointCloud2 " + time_problem;
    warnInput("per-point times ignored",
              "PointCloud2 on " + inputs_->topic(SessionInput::kEgoMotion) + ": " + time_problem +
                  " (" + std::to_string(counts_.clouds_without_times) + " so far)");
  }
  std::vector<CollectorEvent> events;
  try {
    events = takeScan(stamp_s, scan);
  } catch (const std::invalid_argument& error) {
    rejectInput(SessionInput::kEgoMotion, "PointCloud2", error.what());
    return;
  }
  handleEvents(events, stamp_s);
}

void CalibrationSession::skipEgoMessage(const std::string& what, const std::string& problem,
                                        const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!admit(SessionInput::kEgoMotion, publisher, false))
    return;
  rejectInput(SessionInput::kEgoMotion, what, problem);
}

void CalibrationSession::addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                                       const std::string& frame, const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!admit(SessionInput::kEgoMotion, publisher))
    return;
  counts_.ego_stamps.add(stamp_s);
  noteFrame(frame);
  const double sigma_m = config_.ego_motion_sigma_m, sigma_rad = config_.ego_motion_sigma_rad;
  const Eigen::Matrix3d covariance =
      Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  std::vector<CollectorEvent> events;
  record([&](InputRecord& inputs) { inputs.addSensorPose(stamp_s, T_world_sensor, covariance); });
  try {
    events = collector_->addSensorPose(stamp_s, T_world_sensor, covariance);
    if (candidates_)
      candidates_->addSensorPose(stamp_s, T_world_sensor, covariance);
  } catch (const std::invalid_argument& error) {
    rejectInput(SessionInput::kEgoMotion, "sensor pose", error.what());
    return;
  }
  handleEvents(events, stamp_s);
}

void CalibrationSession::flush()
{
  std::lock_guard<std::mutex> lock(mutex_);
  flushLocked();
}

void CalibrationSession::flushLocked()
{
  record([](InputRecord& inputs) { inputs.addFlush(); });
  input_since_flush_ = false;
  handleEvents(collector_->flush(), 0.0);
  if (candidates_)
    candidates_->flush();
}

void CalibrationSession::completeWhenInputEnded()
{
  // Every input silent this long (wall clock): the inputs still waiting for their encoders are
  // concluded as calibrate_bag concludes them at the end of its bags. Mid-stream nothing is: a
  // waiting scan is paired once its encoders come, and concluding it early would reject it.
  if (!input_since_flush_ || !inputs_->inputEnded(now()))
    return;
  flushLocked();
  say(SessionLogLevel::kInfo,
      "the inputs waiting for their encoders were paired or rejected at the end of the input, as "
      "calibrate_bag does at the end of its bags (" +
          std::to_string(store_->pairs().size()) + " pairs)");
}

void CalibrationSession::tick()
{
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::string& warning : inputs_->silentWarnings(now()))
    say(SessionLogLevel::kWarn, warning);
  completeWhenInputEnded();
  store_->writePending();
}

std::size_t CalibrationSession::writePendingPairs()
{
  std::lock_guard<std::mutex> lock(mutex_);
  store_->writePending();
  return store_->unwritten();
}

void CalibrationSession::restart(const std::string& reason, double stamp_s)
{
  char text[200];
  std::snprintf(text, sizeof(text), "at %.3f s: ", stamp_s);
  ++counts_.restart_count;
  if (counts_.restarts.size() < kRestartsKept)
    counts_.restarts.push_back(text + reason);
  warnInput("time went backwards",
            "time went backwards " + std::string(text) + reason +
                ": keyframe pairing, encoder history and odometry restarted (" +
                std::to_string(counts_.restart_count) + " times so far), the " +
                std::to_string(store_->pairs().size()) + " pairs collected are kept");
  last_problem_ = "time went backwards: " + reason;
  // The offset search needs one continuous encoder stream: none until a reset.
  history_broken_ = true;
  encoder_history_.clear();
  if (odometry_)
    odometry_->restart();
}

void CalibrationSession::handleEvents(const std::vector<CollectorEvent>& events, double stamp_s)
{
  for (const CollectorEvent& event : events) {
    switch (event.type) {
      case CollectorEvent::Type::kPair:
        store_->add(event.pair);
        if (odometry_)
          odometry_->addScanMatched(event.pair);
        if (assistant_)
          assistant_->addPair(event.pair);
        if (listener_.pair)
          listener_.pair(event.pair);
        break;
      case CollectorEvent::Type::kRestarted:
        restart(event.reason, stamp_s);
        break;
      case CollectorEvent::Type::kGlitch:
        last_problem_ = event.reason;
        warnInput(event.reason.substr(0, event.reason.find(':')),
                  event.reason + " (counted on /diagnostics)");
        break;
      case CollectorEvent::Type::kRejected:
        // Each reason once as a warning; the counts are on /diagnostics.
        if (rejection_reasons_seen_.insert(event.reason).second) {
          say(SessionLogLevel::kWarn,
              "keyframe interval rejected (first time for this reason; counted on "
              "/diagnostics): " +
                  event.reason);
        }
        break;
      default:
        break;
    }
  }
}

}  // namespace odometry_calibration
