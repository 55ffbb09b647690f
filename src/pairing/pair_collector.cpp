#include "odometry_calibration/pairing/pair_collector.h"

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/pairing/decimated_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

namespace odometry_calibration {
namespace {

constexpr double kOpen = std::numeric_limits<double>::infinity();  ///< a span not closed yet

/// The sweep's velocity, linear in time, from the sensor's motion over its two halves, each
/// `half_s` long: T_first over the first (in the frame at the stamp), T_second over the second
/// (in the frame at mid-sweep). Their mean twists xi_1 = log(T_first) / half_s and xi_2 (its
/// linear part turned into the stamp's frame) are the twist at a quarter and at three quarters
/// of the sweep: a = (xi_2 - xi_1) / half_s, v(stamp) = xi_1 - a half_s / 2.
SensorVelocity linearSweepVelocity(const Pose2& T_first, const Pose2& T_second, double half_s)
{
  const Eigen::Vector3d xi_1 = se2Log(T_first) / half_s;
  const Eigen::Vector3d xi_2_mid = se2Log(T_second) / half_s;
  const double c = std::cos(T_first.theta());
  const double s = std::sin(T_first.theta());
  const Eigen::Vector3d xi_2(c * xi_2_mid.x() - s * xi_2_mid.y(),
                             s * xi_2_mid.x() + c * xi_2_mid.y(), xi_2_mid.z());
  const Eigen::Vector3d a = (xi_2 - xi_1) / half_s;
  const Eigen::Vector3d v = xi_1 - 0.5 * half_s * a;
  return SensorVelocity{v.x(), v.y(), v.z(), a.x(), a.y(), a.z()};
}

}  // namespace

double CollectorStatistics::keyframeVersusChainPercent() const
{
  return chained_m > 0.0 ? 100.0 * (keyframe_along_chain_m / chained_m - 1.0)
                         : std::numeric_limits<double>::quiet_NaN();
}

double CollectorStatistics::keyframeVersusChainStandardErrorPercent() const
{
  const double n = static_cast<double>(scale_check_pairs);
  if (scale_check_pairs < 2 || !(chained_m > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  const double ratio = keyframe_along_chain_m / chained_m;
  // sum (k - R c)^2 expanded into the running sums.
  const double residual2 = keyframe_along_chain_m2 - 2.0 * ratio * chained_times_keyframe_m2 +
                           ratio * ratio * chained_m2;
  return 100.0 * std::sqrt(std::max(0.0, residual2) * n / (n - 1.0)) / chained_m;
}

double roundedUpForAdvice_s(double seconds)
{
  constexpr double kStep_s = 0.05;
  return std::ceil(seconds / kStep_s - 1e-9) * kStep_s;
}

double derivedEncoderGap_s(double median_spacing_s)
{
  return std::isfinite(median_spacing_s)
             ? std::max(kMinEncoderGapS, kEncoderGapPerSpacing * median_spacing_s)
             : kMinEncoderGapS;
}

void validate(const CollectorOptions& o)
{
  auto require = [](bool ok, const char* message) {
    if (!ok)
      throw std::invalid_argument(message);
  };
  require(o.keyframe_interval_s > 0.0 && std::isfinite(o.keyframe_interval_s),
          "keyframe_interval_s must be > 0 s");
  require(std::isfinite(o.time_offset_s) && std::abs(o.time_offset_s) < 5.0,
          "time_offset_s must be within +-5 s");
  require(std::isfinite(o.max_encoder_gap_s) && o.max_encoder_gap_s >= 0.0,
          "max_encoder_gap_s must be >= 0 s (0: derived from the encoder readings' spacing)");
  require(o.min_translation_m >= 0.0 && o.min_rotation_rad >= 0.0,
          "min_translation_m and min_rotation_rad must be >= 0");
  require(o.consistency_translation_m > 0.0 && o.consistency_rotation_rad > 0.0,
          "consistency thresholds must be > 0");
  require((o.covariance_floor.array() >= 0.0).all(), "covariance_floor must be >= 0");
  require(!o.pair_motion_from_chain || o.check_consistency,
          "pair_motion_from_chain needs check_consistency (the consecutive matches)");
  require(o.consecutive_max_rays >= 0, "consecutive_max_rays must be >= 0 (0: every ray)");
  // (Fewer rays than a match needs would fail every coarse match and redo it with every ray.)
  require(o.consecutive_max_rays == 0 || o.consecutive_max_rays >= o.plicp.min_points,
          "consecutive_max_rays must be 0 (every ray) or at least scan_matching.min_points (a "
          "match needs that many points)");
  require(std::isfinite(o.consecutive_min_spacing_s) && o.consecutive_min_spacing_s >= 0.0,
          "consecutive_min_spacing_s must be >= 0 s (0: every scan joins the chain)");
  validate(o.plicp);
}

PairCollector::PairCollector(std::vector<EncoderChannelOptions> channels, CollectorOptions options,
                             MotionPredictor predictor)
    : options_(std::move(options)),
      predictor_(std::move(predictor)),
      track_(channels, std::max(30.0, 4.0 * options_.keyframe_interval_s)),
      glitch_filter_(std::move(channels))
{
  validate(options_);
  // The chain uses only the consecutive matches' poses and statuses; the covariance (which
  // does not change either) would cost time for nothing.
  consecutive_options_ = options_.plicp;
  consecutive_options_.compute_covariance = false;
  if (options_.check_consistency || options_.defer_keyframe_matches)
    matches_ = std::make_unique<MatchQueue>(options_.background_matching &&
                                            std::thread::hardware_concurrency() > 1);
}

PairCollector::~PairCollector() = default;

double PairCollector::encoderGapLimit_s() const
{
  return options_.max_encoder_gap_s > 0.0 ? options_.max_encoder_gap_s
                                          : derivedEncoderGap_s(encoder_spacing_.median_s());
}

std::string PairCollector::configurationConflict() const
{
  constexpr std::size_t kMinSpacings = 10;
  constexpr double kMinGapPerSpacing = 1.5;
  const double spacing_s = encoder_spacing_.median_s();
  if (encoder_spacing_.count() < kMinSpacings || !std::isfinite(spacing_s))
    return "";
  char text[400];
  if (options_.keyframe_interval_s < spacing_s) {
    std::snprintf(text, sizeof(text),
                  "keyframes.interval_s = %.3g s is shorter than the encoder readings' spacing, "
                  "%.3g s (median of %zu): a pair would hold no reading of its own; set it to at "
                  "least %.2f (two spacings)",
                  options_.keyframe_interval_s, spacing_s, encoder_spacing_.count(),
                  roundedUpForAdvice_s(2.0 * spacing_s));
    return text;
  }
  if (!(options_.max_encoder_gap_s > 0.0) ||
      !(options_.max_encoder_gap_s < kMinGapPerSpacing * spacing_s))
    return "";
  const double suggested_s = roundedUpForAdvice_s(derivedEncoderGap_s(spacing_s));
  std::snprintf(text, sizeof(text),
                "keyframes.max_encoder_gap_s = %.3g s is shorter than the encoder readings allow: "
                "they arrive every %.3g s (median of %zu spacings), so most keyframes find no "
                "reading that close; set it to at least %.2f, or remove the key (its default "
                "derives it from the readings)",
                options_.max_encoder_gap_s, spacing_s, encoder_spacing_.count(), suggested_s);
  return text;
}

void PairCollector::reset()
{
  fold(Fold::kAll);
  ready_.clear();
  pending_.clear();
  track_.clear();
  glitch_filter_.reset();
  glitch_spans_.clear();
  encoder_spacing_.clear();
  keyframe_.reset();
  previous_scan_.reset();
  previous_full_scan_.reset();
  chain_valid_ = false;
  last_input_stamp_s_ = -1e300;
  last_scan_stamp_s_ = -1e300;
  previous_keyframe_input_s_ = 0.0;
}

void PairCollector::restart(const std::string& what)
{
  fold(Fold::kAll);  // the events before the restart are returned before it
  std::vector<CollectorEvent> before = std::move(ready_);
  reset();
  ready_ = std::move(before);
  ++statistics_.restarts;
  CollectorEvent event;
  event.type = CollectorEvent::Type::kRestarted;
  // What restarted and what is kept is the caller's to say (the session says it once).
  event.reason = what + " went backwards in time (a looping bag or a clock reset)";
  ready_.push_back(event);
}

std::vector<CollectorEvent> PairCollector::addEncoders(double stamp_s, const Eigen::VectorXd& raw,
                                                       Eigen::VectorXd* accepted)
{
  if (accepted)
    accepted->resize(0);
  ++statistics_.encoder_messages;
  const bool backwards = !track_.empty() && stamp_s < track_.lastStamp();
  if (backwards)
    glitch_filter_.reset();
  // Throws (state unchanged) for a wrong size or a non-finite value.
  EncoderGlitchFilter::Result filtered = glitch_filter_.filter(stamp_s, raw);
  if (filtered.glitch) {
    const EncoderChannelOptions& channel = track_.channels()[filtered.channel];
    ++statistics_.glitches[channel.name];
    if (filtered.wrap_bits > 0)
      statistics_.glitch_wrap_bits[channel.name] = filtered.wrap_bits;
    if (glitch_spans_.empty() || glitch_spans_.back().second < kOpen) {
      glitch_spans_.emplace_back(track_.empty() ? -kOpen : track_.lastStamp(), kOpen);
    }
    while (glitch_spans_.size() > 1000 || glitch_spans_.front().second < stamp_s - 60.0)
      glitch_spans_.pop_front();
    CollectorEvent event;
    event.type = CollectorEvent::Type::kGlitch;
    std::ostringstream reason;
    reason << "encoder glitch on joint '" << channel.name << "': an increment of "
           << filtered.increment << " units, beyond " << channel.max_rate_per_s
           << " units/s (the joint's max_turns_per_s) or unsteady against the readings before "
              "(a spike or a stray reading between real ones); reading skipped";
    event.reason = reason.str();
    queueEvent(event, false);
    return takeEvents();
  }
  last_input_stamp_s_ = std::max(last_input_stamp_s_, stamp_s);
  encoder_spacing_.add(stamp_s);
  if (accepted)
    *accepted = filtered.corrected;
  if (!glitch_spans_.empty() && glitch_spans_.back().second == kOpen) {
    // After skipped spikes the counts go on from the reading before them: nothing is unknown
    // between the two, and pairs may span them. After a jump they are unknown there.
    if (filtered.continuous)
      glitch_spans_.pop_back();
    else
      glitch_spans_.back().second = stamp_s;
  }
  if (track_.add(stamp_s, filtered.corrected) == EncoderTrack::AddResult::kRestarted) {
    // The encoder history is gone: so is the keyframe it would have been paired with.
    restart("the encoder stream");
    track_.add(stamp_s, filtered.corrected);
    return takeEvents();
  }
  processReadyScans(false);
  return takeEvents();
}

std::vector<CollectorEvent> PairCollector::flush()
{
  processReadyScans(true);
  fold(Fold::kAll);
  return std::exchange(ready_, {});
}

void PairCollector::processReadyScans(bool all)
{
  while (!pending_.empty()) {
    // A scan whose sweep is compensated waits for the encoders of its whole sweep.
    const auto& front_scan = pending_.front().scan;
    const double sweep_s =
        options_.compensate_sweep && front_scan && front_scan->hasRayTimes() && predictor_
            ? front_scan->sweepDuration()
            : 0.0;
    const double needed = pending_.front().stamp_s + sweep_s + options_.time_offset_s;
    // The cubic interpolation's slope at the reading after `needed` takes the one after it.
    const std::size_t readings_needed =
        options_.encoder_interpolation == EncoderInterpolation::kCubic ? 2 : 1;
    const bool encoders_there = track_.readingsFrom(needed) >= readings_needed;
    // Input this much later shows the encoders will not come (a gap, a dead stream).
    const bool given_up = last_input_stamp_s_ > needed + encoderGapLimit_s() && !encoders_there;
    if (!all && !encoders_there && !given_up)
      break;
    const PendingInput input = pending_.front();
    pending_.pop_front();
    if (input.scan)
      processScan(input.stamp_s, input.scan, input.chain_scan);
    else
      processPose(input.stamp_s, input.T_world_sensor, input.covariance);
  }
}

std::optional<std::vector<EncoderSample>> PairCollector::encoderWindow(double start_s, double end_s,
                                                                       std::string* reason) const
{
  const double from = start_s + options_.time_offset_s;
  const double to = end_s + options_.time_offset_s;
  const double gap_limit_s = encoderGapLimit_s();
  if (!track_.covers(from, gap_limit_s) || !track_.covers(to, gap_limit_s)) {
    *reason = kNoEncoderReadingReason;
    return std::nullopt;
  }
  if (track_.largestGap(from, to) > gap_limit_s) {
    *reason = kEncoderGapReason;
    return std::nullopt;
  }
  // Between the readings around a glitch the counts are unknown (a jump was removed), and so
  // is any value interpolated there.
  for (const auto& [before_s, after_s] : glitch_spans_) {
    if (before_s < to && after_s > from) {
      *reason = "encoder glitch in the interval";
      return std::nullopt;
    }
  }

  return track_.between(from, to, options_.encoder_interpolation);
}

Pose2 PairCollector::predict(const std::vector<EncoderSample>& window) const
{
  return predictor_ ? predictor_(window) : Pose2();
}

bool PairCollector::tooLittleMotion(const std::vector<EncoderSample>& window) const
{
  if (!predictor_ || (options_.min_translation_m <= 0.0 && options_.min_rotation_rad <= 0.0))
    return false;
  const Pose2 motion = predictor_(window);
  return std::hypot(motion.x(), motion.y()) < options_.min_translation_m &&
         std::abs(motion.theta()) < options_.min_rotation_rad;
}

std::vector<CollectorEvent> PairCollector::addScan(double stamp_s, const Scan& scan)
{
  ++statistics_.scans;
  if (stamp_s < last_scan_stamp_s_) {
    restart("the scan stream");
    return takeEvents();
  }
  last_scan_stamp_s_ = stamp_s;
  last_input_stamp_s_ = std::max(last_input_stamp_s_, stamp_s);
  // Prepared later, by the first match that needs it (possibly on the matching thread): a scan
  // that does not become a keyframe is prepared only as the chain sees it.
  auto prepared = std::make_shared<LazyPreparedScan>(scan, options_.plicp.line_fit);
  const int rays = static_cast<int>(scan.ranges_m.size());
  const int max_rays = options_.consecutive_max_rays;
  const int stride = max_rays > 0 ? (rays + max_rays - 1) / max_rays : 1;
  auto chain_scan =
      options_.check_consistency && stride > 1
          ? std::make_shared<LazyPreparedScan>(decimateRays(scan, stride), options_.plicp.line_fit)
          : prepared;
  pending_.push_back(
      {stamp_s, std::move(prepared), std::move(chain_scan), Pose2(), Eigen::Matrix3d::Zero()});
  processReadyScans(false);
  return takeEvents();
}

std::optional<CollectorEvent> PairCollector::unpairedInput(
    double stamp_s, const std::function<CollectorEvent(CollectorEvent)>& start_keyframe,
    std::vector<EncoderSample>* window)
{
  if (!keyframe_) {
    previous_keyframe_input_s_ = stamp_s;
    CollectorEvent event;
    event.type = CollectorEvent::Type::kKeyframe;
    return start_keyframe(event);
  }
  const bool keyframe_time = reachesKeyframeTime(stamp_s);
  previous_keyframe_input_s_ = stamp_s;
  if (!keyframe_time)
    return CollectorEvent();
  std::string reason;
  auto found = encoderWindow(keyframe_->stamp_s, stamp_s, &reason);
  if (!found)
    return start_keyframe(reject(reason));
  if (tooLittleMotion(*found)) {
    if (stamp_s - keyframe_->stamp_s < 4.0 * options_.keyframe_interval_s)
      return CollectorEvent();  // wait for more motion
    return start_keyframe(
        reject("too little motion (keyframes.min_translation_m/min_rotation_rad)"));
  }
  *window = std::move(*found);
  return std::nullopt;
}

bool PairCollector::reachesKeyframeTime(double stamp_s) const
{
  if (!keyframe_)
    return true;
  if (!keyframe_->scan) {
    // A pose source (a tracker: tens of poses a second, unevenly spaced): the first pose at
    // least T after the keyframe (within a stamp's rounding), so that no pair is shorter than T.
    // At such rates half a spacing is a few per cent of T, and the pairs of the scan rule below
    // scored worse on held-out tracker data (docs/results.md, "The tracker log").
    constexpr double kStampRoundingS = 1e-6;
    return stamp_s - keyframe_->stamp_s >= options_.keyframe_interval_s - kStampRoundingS;
  }
  // A scan: the input nearest to keyframe + T: the first one past T minus half the input period
  // (the last gap between inputs as the period). Without the half period, T = 0.3 s on a 10 Hz
  // laser waited for the 0.4 s scan whenever the stamps' sum came out a rounding error short of 0.3
  // s.
  const double half_period_s = 0.5 * std::max(0.0, stamp_s - previous_keyframe_input_s_);
  return stamp_s - keyframe_->stamp_s >= options_.keyframe_interval_s - half_period_s;
}

bool PairCollector::joinsChain(double stamp_s) const
{
  // At most half of T: a spacing of T or more would chain only the keyframe scans, one coarse
  // copy of the keyframe match, which repeats its failures instead of checking them.
  const double spacing_s =
      std::min(options_.consecutive_min_spacing_s, 0.5 * options_.keyframe_interval_s);
  // Stamps a rounding error short of the spacing join (0.15 s is 6 periods of a 40 Hz laser).
  constexpr double kStampToleranceS = 1e-4;
  // Every scan the keyframe rule considers joins, so that the chain always ends at the scan a
  // keyframe match ends at (or that starts the next keyframe).
  return spacing_s <= 0.0 || !previous_scan_ || reachesKeyframeTime(stamp_s) ||
         stamp_s - previous_chain_stamp_s_ >= spacing_s - kStampToleranceS;
}

void PairCollector::compensateSweep(double stamp_s, LazyPreparedScan& prepared_scan)
{
  // The sweep's motion: the prior model's prediction over the sweep itself [stamp, stamp +
  // sweep duration], over each half of it, as a velocity linear in time
  // (linearSweepVelocity), set before anything prepares the scan. A constant velocity leaves
  // the rays in mid-sweep behind while the robot speeds up its turn (alpha S^2 / 8: 12 mrad at
  // 3 rad/s^2 over a 0.18 s sweep), which put the time offset 3-4 ms late on a simulated
  // 360-degree scanner even with 50 Hz encoders. Without the encoders of the whole sweep (the
  // stream ended), a constant velocity, the prediction since the previous scan: one sweep
  // late, it misjudges the motion while the robot accelerates (on a simulated 10 Hz, 16-beam
  // lidar it biased the radii 0.6 % low).
  if (!(options_.compensate_sweep && predictor_ && prepared_scan.hasRayTimes()))
    return;
  std::string reason;
  const double sweep_end_s = stamp_s + prepared_scan.sweepDuration();
  const bool sweep_covered = prepared_scan.sweepDuration() > 0.0 && !track_.empty() &&
                             track_.lastStamp() >= sweep_end_s + options_.time_offset_s;
  if (sweep_covered) {
    const double mid_s = stamp_s + 0.5 * prepared_scan.sweepDuration();
    const auto first = encoderWindow(stamp_s, mid_s, &reason);
    const auto second = first ? encoderWindow(mid_s, sweep_end_s, &reason) : std::nullopt;
    if (first && second && mid_s > stamp_s) {
      prepared_scan.setSweepVelocity(
          linearSweepVelocity(predict(*first), predict(*second), mid_s - stamp_s));
      return;
    }
  }
  const double from_s =
      sweep_covered ? stamp_s : (previous_scan_ ? previous_scan_stamp_s_ : stamp_s);
  const double to_s = sweep_covered ? sweep_end_s : stamp_s;
  if (to_s > from_s) {
    if (const auto window = encoderWindow(from_s, to_s, &reason)) {
      const Eigen::Vector3d xi = se2Log(predict(*window)) / (to_s - from_s);
      prepared_scan.setSweepVelocity({xi(0), xi(1), xi(2)});
    }
  }
}

void PairCollector::submitConsecutiveMatch(double stamp_s,
                                           const std::shared_ptr<LazyPreparedScan>& prepared,
                                           const std::shared_ptr<LazyPreparedScan>& chain_scan)
{
  // Consecutive-scan chain: the reference for the keyframe match's consistency. The match is
  // submitted now, with the guess from the encoders as they are now, and folded in before the
  // next keyframe decision; while its predecessors are unfolded, whether the chain is still
  // valid is not known yet, so it is submitted and the fold applies the rule.
  if (!(options_.check_consistency && previous_scan_ && (chain_valid_ || !unfolded_.empty())))
    return;
  std::string reason;
  const auto window = encoderWindow(previous_chain_stamp_s_, stamp_s, &reason);
  const Pose2 guess = window ? predict(*window) : Pose2();
  Unfolded entry;
  entry.consecutive =
      matches_->submit(previous_scan_, chain_scan, guess, consecutive_options_, options_.matcher,
                       // A failed coarse match is matched again with every ray.
                       chain_scan != prepared ? previous_full_scan_ : nullptr,
                       chain_scan != prepared ? prepared : nullptr);
  unfolded_.push_back(std::move(entry));
}

void PairCollector::startKeyframe(double stamp_s, std::shared_ptr<const LazyPreparedScan> scan,
                                  const Pose2& T_world_sensor, const CollectorEvent& event)
{
  keyframe_ = Keyframe{stamp_s, std::move(scan), T_world_sensor};
  ++statistics_.keyframes;
  // The consecutive matches queued so far belong to the ending chain.
  queueEvent(event, true);
}

void PairCollector::processScan(double stamp_s, std::shared_ptr<LazyPreparedScan> prepared,
                                std::shared_ptr<LazyPreparedScan> chain_scan)
{
  compensateSweep(stamp_s, *prepared);
  if (joinsChain(stamp_s)) {
    if (chain_scan != prepared)
      chain_scan->setSweepVelocity(prepared->sweepVelocity());
    submitConsecutiveMatch(stamp_s, prepared, chain_scan);
    previous_scan_ = chain_scan;
    previous_full_scan_ = prepared;
    previous_chain_stamp_s_ = stamp_s;
  }
  previous_scan_stamp_s_ = stamp_s;

  auto start_keyframe = [&](const CollectorEvent& event) {
    startKeyframe(stamp_s, prepared, Pose2(), event);
    return CollectorEvent();
  };
  std::vector<EncoderSample> window;
  if (unpairedInput(stamp_s, start_keyframe, &window))
    return;
  // The keyframe match: on the match queue with defer_keyframe_matches, else here while the
  // background thread works through the consecutive matches. Concluded when folded, with the
  // chain up to this scan.
  Unfolded entry;
  const Pose2 guess = predict(window);
  if (options_.defer_keyframe_matches) {
    entry.keyframe =
        matches_->submit(keyframe_->scan, prepared, guess, options_.plicp, options_.matcher);
  } else {
    entry.keyframe = std::make_shared<MatchJob>();
    entry.keyframe->result = timedMatch(*keyframe_->scan, *prepared, guess, options_.plicp,
                                        &entry.keyframe->preparation_time_s,
                                        &entry.keyframe->matching_time_s, options_.matcher);
    entry.keyframe->done = true;
  }
  entry.event.pair.start_stamp_s = keyframe_->stamp_s;
  entry.event.pair.end_stamp_s = stamp_s;
  entry.event.pair.encoder_samples = std::move(window);
  entry.ends_chain = true;
  keyframe_ = Keyframe{stamp_s, prepared, Pose2()};
  ++statistics_.keyframes;
  unfolded_.push_back(std::move(entry));
}

std::vector<CollectorEvent> PairCollector::addSensorPose(double stamp_s,
                                                         const Pose2& T_world_sensor,
                                                         const Eigen::Matrix3d& covariance)
{
  if (stamp_s < last_scan_stamp_s_) {
    restart("the sensor pose stream");
    return takeEvents();
  }
  last_scan_stamp_s_ = stamp_s;
  last_input_stamp_s_ = std::max(last_input_stamp_s_, stamp_s);
  pending_.push_back({stamp_s, nullptr, nullptr, T_world_sensor, covariance});
  processReadyScans(false);
  return takeEvents();
}

void PairCollector::processPose(double stamp_s, const Pose2& T_world_sensor,
                                const Eigen::Matrix3d& covariance)
{
  auto start_keyframe = [&](const CollectorEvent& event) {
    startKeyframe(stamp_s, nullptr, T_world_sensor, event);
    return CollectorEvent();
  };
  std::vector<EncoderSample> window;
  if (unpairedInput(stamp_s, start_keyframe, &window))
    return;
  MotionPair interval;
  interval.start_stamp_s = keyframe_->stamp_s;
  interval.end_stamp_s = stamp_s;
  interval.encoder_samples = std::move(window);
  const CollectorEvent pair = pairEvent(
      std::move(interval), between(keyframe_->T_world_sensor, T_world_sensor), covariance);
  startKeyframe(stamp_s, nullptr, T_world_sensor, pair);
}

}  // namespace odometry_calibration
