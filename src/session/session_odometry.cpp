#include "odometry_calibration/session/session_odometry.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace odometry_calibration {
namespace {

/// Scan-matched and odometry paths keep this many seconds of corrected sensor poses to bridge
/// rejected keyframe intervals.
constexpr double kRecentPoseHistoryS = 60.0;

template <typename T>
void dropOldest(std::deque<T>* poses, int max_poses)
{
  while (static_cast<int>(poses->size()) > max_poses)
    poses->pop_front();
}

OdometryState stateOf(const OdometryIntegrator& odometry, double stamp_s)
{
  OdometryState state;
  state.stamp_s = stamp_s;
  state.pose = odometry.pose();
  state.tracks_base = odometry.tracksBase();
  state.covariance = odometry.covariance();
  state.velocity = odometry.velocity();
  // The velocity's spread: the odometry's growth over one window of its model, per second.
  const double interval_s = odometry.segmentLength();
  state.velocity_covariance = odometry.windowCovariance() / (interval_s * interval_s);
  return state;
}

}  // namespace

SessionOdometry::SessionOdometry(const std::vector<EncoderChannelOptions>& channels,
                                 const SessionOdometryOptions& options)
    : options_(options), decoder_(channels)
{
}

SessionOdometry::SessionOdometry(const SessionOdometry& other)
    : options_(other.options_),
      decoder_(other.decoder_),
      last_encoder_stamp_s_(other.last_encoder_stamp_s_),
      last_path_stamp_s_(other.last_path_stamp_s_),
      nominal_(other.nominal_ ? std::make_unique<OdometryIntegrator>(*other.nominal_) : nullptr),
      corrected_(other.corrected_ ? std::make_unique<OdometryIntegrator>(*other.corrected_)
                                  : nullptr),
      nominal_path_(other.nominal_path_),
      corrected_path_(other.corrected_path_),
      path_samples_(other.path_samples_),
      path_samples_start_(other.path_samples_start_),
      recent_sensor_poses_(other.recent_sensor_poses_),
      scan_matched_sensor_poses_(other.scan_matched_sensor_poses_),
      scan_matched_end_s_(other.scan_matched_end_s_),
      generation_(other.generation_),
      continuity_(other.continuity_)
{
}

void SessionOdometry::setNominal(std::unique_ptr<OdometryIntegrator> nominal)
{
  nominal_ = std::move(nominal);
}

void SessionOdometry::setCorrected(std::unique_ptr<OdometryIntegrator> corrected)
{
  corrected_ = std::move(corrected);
}

std::optional<OdometryState> SessionOdometry::add(double encoder_stamp_s,
                                                  const Eigen::VectorXd& raw, double time_offset_s)
{
  if (!(encoder_stamp_s > last_encoder_stamp_s_)) {
    if (!(encoder_stamp_s < last_encoder_stamp_s_))
      return std::nullopt;  // a repeated stamp adds nothing
    restart();              // the collector has reported (and restarted) already
  }
  last_encoder_stamp_s_ = encoder_stamp_s;
  // Published in the laser's clock: encoder time t_e shows the robot at laser time t_e - tau.
  const EncoderSample sample{encoder_stamp_s - time_offset_s, decoder_.decode(raw)};
  if (nominal_)
    nominal_->add(sample);
  if (!corrected_)
    return std::nullopt;
  corrected_->add(sample);
  keepRecentSensorPose(sample.stamp_s, corrected_->sensorPose());
  if (sample.stamp_s - last_path_stamp_s_ >= options_.path_spacing_s)
    addToPaths(sample, corrected_->pose());
  OdometryState state = stateOf(*corrected_, sample.stamp_s);
  state.continuity = continuity_;
  return state;
}

void SessionOdometry::keepRecentSensorPose(double stamp_s, const Pose2& T_odom_sensor)
{
  recent_sensor_poses_.emplace_back(stamp_s, T_odom_sensor);
  if (recent_sensor_poses_.front().first < stamp_s - kRecentPoseHistoryS) {
    recent_sensor_poses_.erase(recent_sensor_poses_.begin(),
                               recent_sensor_poses_.begin() + recent_sensor_poses_.size() / 2);
  }
}

void SessionOdometry::addToPaths(const EncoderSample& sample, const Pose2& pose)
{
  last_path_stamp_s_ = sample.stamp_s;
  corrected_path_.push_back({sample.stamp_s, pose});
  dropOldest(&corrected_path_, options_.path_max_poses);
  path_samples_.push_back(sample);
  if (static_cast<int>(path_samples_.size()) > options_.path_max_poses) {
    path_samples_.pop_front();
    path_samples_start_ = corrected_path_.front().pose;
  }
  if (nominal_) {
    nominal_path_.push_back({sample.stamp_s, nominal_->pose()});
    dropOldest(&nominal_path_, options_.path_max_poses);
  }
}

void SessionOdometry::restart()
{
  ++generation_;
  ++continuity_;
  decoder_.reset();
  last_encoder_stamp_s_ = -1e300;
  last_path_stamp_s_ = -1e300;
  if (nominal_)
    nominal_->reset();
  if (corrected_)
    corrected_->reset();
  nominal_path_.clear();
  corrected_path_.clear();
  path_samples_.clear();
  path_samples_start_ = Pose2();
  scan_matched_sensor_poses_.clear();
  recent_sensor_poses_.clear();
  scan_matched_end_s_.reset();
}

void SessionOdometry::addScanMatched(const MotionPair& pair)
{
  Pose2 start;
  if (scan_matched_end_s_ && std::abs(*scan_matched_end_s_ - pair.start_stamp_s) < 1e-9 &&
      !scan_matched_sensor_poses_.empty()) {
    start = scan_matched_sensor_poses_.back().pose;
  } else {
    const auto after = std::lower_bound(
        recent_sensor_poses_.begin(), recent_sensor_poses_.end(), pair.start_stamp_s,
        [](const std::pair<double, Pose2>& entry, double stamp) { return entry.first < stamp; });
    if (after != recent_sensor_poses_.end())
      start = after->second;
    else if (!recent_sensor_poses_.empty())
      start = recent_sensor_poses_.back().second;
    scan_matched_sensor_poses_.push_back({pair.start_stamp_s, start});
  }
  scan_matched_sensor_poses_.push_back({pair.end_stamp_s, start * pair.sensor_motion});
  scan_matched_end_s_ = pair.end_stamp_s;
  dropOldest(&scan_matched_sensor_poses_, options_.path_max_poses);
}

OdometryReplayInput SessionOdometry::replayInput() const
{
  return {{path_samples_.begin(), path_samples_.end()}, path_samples_start_, generation_};
}

OdometryReplay SessionOdometry::replay(const OdometryReplayInput& input,
                                       std::unique_ptr<OdometryIntegrator> integrator)
{
  OdometryReplay replay{std::move(integrator), {}, input.generation};
  replay.integrator->restartAt(input.start);
  for (const EncoderSample& sample : input.samples) {
    if (replay.integrator->add(sample))
      replay.path.push_back({sample.stamp_s, replay.integrator->pose()});
  }
  return replay;
}

void SessionOdometry::swapCorrected(OdometryReplay* replay)
{
  if (replay->integrator) {
    if (replay->generation != generation_) {  // restarted while integrating: start afresh
      replay->integrator->reset();
      replay->path.clear();
    }
    // What arrived while integrating (the integrator skips the samples it has), then the newest.
    for (const EncoderSample& sample : path_samples_) {
      if (replay->integrator->add(sample))
        replay->path.push_back({sample.stamp_s, replay->integrator->pose()});
    }
    if (corrected_ && corrected_->lastSample())
      replay->integrator->add(*corrected_->lastSample());
  }
  std::swap(corrected_, replay->integrator);
  ++continuity_;
  std::vector<StampedPose2> replaced(corrected_path_.begin(), corrected_path_.end());
  corrected_path_.assign(replay->path.begin(), replay->path.end());
  replay->path = std::move(replaced);
  replay->generation = generation_;
}

OdometryPaths SessionOdometry::paths(const Pose2& T_base_sensor) const
{
  OdometryPaths paths;
  paths.nominal.assign(nominal_path_.begin(), nominal_path_.end());
  paths.corrected.assign(corrected_path_.begin(), corrected_path_.end());
  const Pose2 T_sensor_base = T_base_sensor.inverse();
  for (const StampedPose2& entry : scan_matched_sensor_poses_)
    paths.scan_matched.push_back({entry.stamp_s, entry.pose * T_sensor_base});
  return paths;
}

}  // namespace odometry_calibration
