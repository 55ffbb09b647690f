// Turns live streams into calibration pairs: encoder readings into an
// EncoderTrack; scans (or sensor poses from another ego-motion source) into keyframes every
// T seconds; each new keyframe matched against the previous one with PLICP, the encoder-
// predicted motion as initial guess; the result checked against the composition of the
// consecutive-scan matches over the same interval, so that matches that fail silently (fast
// motion, few features) are rejected without trusting any model being fitted.
//
// The live node and the offline bag tool feed the same collector in timestamp order, so they
// produce the same pairs.
//
// Speed: the consecutive-scan matches run on a background thread (match_queue.h) while the
// caller goes on with the next messages; they are folded into the chain, in order and with the
// rules of a one-threaded run, when a keyframe interval ends (and before statistics() or
// reset() answer). Every match's inputs are fixed when it is submitted, so the events, pairs
// and statistics are the same as if each match ran at once, whatever the threads' timing.
// Offline (defer_keyframe_matches) the keyframe matches are queued too and their events come a
// few calls later, in the same order: which keyframes are matched never depends on a match.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/data/encoder_glitch_filter.h"
#include "odometry_calibration/data/encoder_track.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/data/stream_spacing.h"
#include "odometry_calibration/pairing/match_queue.h"
#include "odometry_calibration/scan/plicp.h"

namespace odometry_calibration {

/// Options of the keyframe pairing. Times in seconds, lengths in metres, angles in radians.
struct CollectorOptions
{
  /// Keyframe spacing T [s]. Real logs' stamps jitter by tens of ms: keep T >= 0.3 s so the
  /// jitter stays a small part of each interval (shorter pairs bias the wheel radius low).
  double keyframe_interval_s = 0.5;
  /// Optional minimum motion of a pair, as the prior model predicts it from the encoders: a
  /// keyframe interval where the robot moved less than both thresholds is extended (up to four
  /// intervals, then dropped as "too little motion"), so that standing still makes no pairs.
  /// 0 = off. Needs a predictor. [m], [rad]
  double min_translation_m = 0.0;
  double min_rotation_rad = 0.0;
  /// Compensate the motion during each scan's sweep (scans with ray times: time_increment_s or
  /// ray_times_s), with the sensor velocity the prior model predicts over the sweep itself,
  /// linear in time from its two halves (a scan waits for its sweep's encoders; without them, a
  /// constant velocity over the interval since the previous scan).
  bool compensate_sweep = true;
  /// Encoder values are taken at scan time + time_offset_s [s] (clock offset between streams).
  double time_offset_s = 0.0;
  /// A pair is dropped when the encoder stream has a gap longer than this inside it, or no
  /// reading this close to one of its keyframes [s]. 0: derived from the data,
  /// max(kMinEncoderGapS, kEncoderGapPerSpacing x the median spacing of the readings so far), so
  /// that a robot logging its encoders at 4 Hz pairs as one logging them at 50 Hz.
  double max_encoder_gap_s = 0.0;
  /// Match consecutive scans too and reject a keyframe match that disagrees with their
  /// composition by more than the two thresholds below.
  bool check_consistency = true;
  double consistency_translation_m = 0.03;
  double consistency_rotation_rad = 0.02;
  /// The consecutive-scan chain matches at most this many rays of each scan, every k-th ray
  /// with k = ceil(rays / consecutive_max_rays) (decimated_scan.h); the keyframe matches use
  /// every ray. 0: every ray. The chain only checks the keyframe matches: on the 60-minute
  /// 720-ray benchmark bag 180 rays keep the same pairs but one and cost a third of the CPU;
  /// every scan that does not become a keyframe is then prepared only at the coarse spacing.
  /// A consecutive match that fails on the coarse scans is matched again with every ray (the
  /// chain then fails only where the full scans fail too). The scale check below then
  /// compares the keyframe matches with the coarse chain.
  int consecutive_max_rays = 0;
  /// The consecutive-scan chain takes a scan only when it is at least this long after the
  /// chain's previous scan, or when the keyframe rule considers it (a scan about T after the
  /// keyframe, unpairedInput: the keyframe scans are always in the chain), so that the chain's
  /// cost does not grow with the laser's rate. A skipped scan is neither matched nor prepared.
  /// 0: every scan. E.g. 0.25 s at T = 0.5 s chains keyframe, keyframe + 0.3 s and the next
  /// keyframe on a 10 Hz laser (2 matches per interval instead of 5). At most T / 2 is used
  /// (more would leave one chain match per interval, the keyframe match's own scans); stamps
  /// within 0.1 ms short of the spacing count as reaching it. [s]
  double consecutive_min_spacing_s = 0.0;
  /// The pair's measured motion: the keyframe match (false), or the composition of the
  /// consecutive matches over the same interval (true; needs check_consistency, the pair keeps
  /// the keyframe match's covariance and is dropped when a consecutive match failed).
  bool pair_motion_from_chain = false;
  /// How the encoder values at the keyframes' times (+ time_offset_s) are taken between readings.
  EncoderInterpolation encoder_interpolation = EncoderInterpolation::kCubic;
  /// The scan matcher of both kinds of matches; empty: matchScans (scan/plicp.h). For
  /// comparisons with other implementations (match_queue.h).
  ScanMatcher matcher;
  /// Added to every pair's covariance diagonal: unmodelled errors (stamp jitter, the sweep)
  /// that the matcher's own covariance does not see [m^2, m^2, rad^2].
  Eigen::Vector3d covariance_floor{1e-6, 1e-6, 1e-6};
  /// Run the consecutive-scan matches on a background thread (on machines with more than one
  /// core). The events, pairs and statistics are the same either way; off, every match runs
  /// in the calling thread.
  bool background_matching = true;
  /// Offline runs (calibrate_bag): the keyframe matches run on the match queue too, beside the
  /// consecutive ones, and each keyframe interval's event (pair or rejection) is returned by a
  /// later call once its match is done (flush() returns the rest), so that the calling thread
  /// goes on with the next messages and both cores match. The events come in the same order,
  /// with the same contents, and the statistics are the same; only the call that returns an
  /// event differs. Off (the live node, the tests): every event is returned by the call that
  /// made it.
  bool defer_keyframe_matches = false;
  /// The scan matcher, with the line fits of every scan it prepares (plicp.line_fit).
  PlicpOptions plicp;
};

/// The derived encoder gap limit (CollectorOptions::max_encoder_gap_s = 0): never below this
/// [s], and this many median encoder spacings above it (a reading late by one and a half
/// periods still pairs; a stream silent for that long has dropped readings) [-].
constexpr double kMinEncoderGapS = 0.25;
constexpr double kEncoderGapPerSpacing = 2.5;

/// The encoder gap limit the data supports for readings `median_spacing_s` apart (NaN: not
/// measured yet): max(kMinEncoderGapS, kEncoderGapPerSpacing x the spacing) [s].
double derivedEncoderGap_s(double median_spacing_s);

/// `seconds` rounded up to the next 0.05 s: a value to suggest for a key in a message [s].
double roundedUpForAdvice_s(double seconds);

/// Throws std::invalid_argument naming the first invalid option.
void validate(const CollectorOptions& options);

/// The rejections of keyframe intervals for want of encoder readings (CollectorStatistics::
/// rejected's keys): none close enough to a keyframe, or a pause inside the interval.
inline constexpr const char* kNoEncoderReadingReason =
    "no encoder reading within keyframes.max_encoder_gap_s of a keyframe";
inline constexpr const char* kEncoderGapReason =
    "encoder readings paused longer than keyframes.max_encoder_gap_s";

/// Predicts the sensor's motion over encoder samples (e.g. the nominal model); used as the
/// scan matcher's initial guess. Without one, the guess is no motion.
using MotionPredictor = std::function<Pose2(const std::vector<EncoderSample>&)>;

/// What happened to one input.
struct CollectorEvent
{
  enum class Type
  {
    kNothing,    ///< stored (e.g. a scan between keyframes)
    kKeyframe,   ///< first keyframe, or a new one after a rejected pair
    kPair,       ///< a pair was produced (`pair`)
    kRejected,   ///< a keyframe interval gave no pair (`reason`)
    kRestarted,  ///< time went backwards: keyframes reset, collected pairs kept
    kGlitch,     ///< an encoder reading skipped as a glitch (`reason` names the joint)
  };
  Type type = Type::kNothing;
  std::string reason;
  MotionPair pair;
};

/// Counters for diagnostics and reports.
struct CollectorStatistics
{
  std::size_t encoder_messages = 0;
  std::size_t scans = 0;
  std::size_t keyframes = 0;
  std::size_t pairs = 0;
  std::size_t consecutive_matches = 0;
  std::size_t consecutive_failures = 0;
  /// Consecutive matches that failed on the decimated scans and were matched again with
  /// every ray (consecutive_max_rays), counted like consecutive_matches.
  std::size_t consecutive_rematched_all_rays = 0;
  std::size_t restarts = 0;
  std::size_t unverified_pairs = 0;  ///< pairs kept without the consistency check (it failed)
  std::map<std::string, std::size_t> rejected;  ///< reason -> count
  /// The encoder readings' median spacing over the last 100 [s] (NaN before two readings), how
  /// many spacings it is over, and the gap limit in use (max_encoder_gap_s, or derived) [s].
  double encoder_spacing_median_s = 0.0;
  std::size_t encoder_spacings = 0;
  double max_encoder_gap_s = 0.0;
  std::map<std::string, std::size_t> glitches;  ///< joint -> readings skipped as encoder glitches
  /// joint -> the counter size 2^bits its glitches' steps were whole turns of (a wrap that no
  /// joints[].counter_bits describes; EncoderGlitchFilter::counterWrapBits)
  std::map<std::string, int> glitch_wrap_bits;
  /// Scale check of the scan matcher (check_consistency): over the pairs that passed it, the
  /// summed length of the chained consecutive matches [m] and the summed keyframe matches
  /// projected on the chain's direction [m] (chains under 1 cm left out). An unbiased matcher
  /// gives the same sum both ways; on the Mines log the keyframe matches read 0.44 % longer.
  double chained_m = 0.0;
  double keyframe_along_chain_m = 0.0;
  std::size_t scale_check_pairs = 0;
  /// Sums of squares and products of the pairs' two lengths (chain c, keyframe k), for the
  /// standard error: c^2, k^2, c k [m^2].
  double chained_m2 = 0.0;
  double keyframe_along_chain_m2 = 0.0;
  double chained_times_keyframe_m2 = 0.0;
  /// 100 (keyframe_along_chain_m / chained_m - 1) [%], NaN without a compared pair.
  double keyframeVersusChainPercent() const;
  /// Its standard error [%], the pairs taken as independent: 100 sqrt(n / (n - 1) sum (k - R
  /// c)^2) / sum c with R = sum k / sum c (NaN with fewer than two pairs).
  double keyframeVersusChainStandardErrorPercent() const;
  double preparation_time_s = 0.0;  ///< thread time preparing scans (points, lines) [s]
  double matching_time_s = 0.0;     ///< thread time matching scans, both kinds [s]
};

/// The pairing state machine.
class PairCollector
{
public:
  PairCollector(std::vector<EncoderChannelOptions> channels, CollectorOptions options,
                MotionPredictor predictor = nullptr);
  ~PairCollector();
  PairCollector(const PairCollector&) = delete;
  PairCollector& operator=(const PairCollector&) = delete;

  /// A raw encoder reading (one value per channel). Throws std::invalid_argument for bad
  /// readings (the caller reports them); a time going backwards restarts the pairing. Scans
  /// waiting for encoder data up to their time are processed now (hence the events). A reading
  /// beyond a channel's max_rate_per_s, or not steady, is a glitch (encoder_glitch_filter.h):
  /// skipped, counted, one kGlitch event; no pair is made across a jump the filter absorbed
  /// (pairs may span skipped spikes: the counts go on across them). `accepted` (optional): the
  /// reading to use for odometry, jumps removed; empty for a glitch.
  std::vector<CollectorEvent> addEncoders(double stamp_s, const Eigen::VectorXd& raw,
                                          Eigen::VectorXd* accepted = nullptr);

  /// A laser scan stamped with the laser clock. It waits until the encoder stream has reached
  /// its time (+ time_offset_s), or until max_encoder_gap_s later input shows it never will:
  /// messages of the two streams with equal stamps may come in either order.
  std::vector<CollectorEvent> addScan(double stamp_s, const Scan& scan);

  /// Processes every waiting scan now (end of a bag).
  std::vector<CollectorEvent> flush();

  /// A sensor pose from another ego-motion source (tracker, visual odometry), in place of
  /// scans: the pair's displacement is the relative pose, with `covariance`. Waits for the
  /// encoders like addScan.
  std::vector<CollectorEvent> addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                                            const Eigen::Matrix3d& covariance);

  /// Forgets keyframes and encoder history (pairs already produced are the caller's; with
  /// defer_keyframe_matches, the events not returned yet are dropped).
  void reset();

  /// The counters, with every consecutive match submitted so far counted.
  const CollectorStatistics& statistics() const;
  /// The encoder gap limit in use: max_encoder_gap_s, or derived from the readings' spacing
  /// (derivedEncoderGap_s) when it is 0 [s].
  double encoderGapLimit_s() const;
  /// A configured value the encoder readings contradict, once at least 10 spacings measure
  /// them: a max_encoder_gap_s shorter than 1.5 median spacings (most keyframes would find no
  /// reading), or a keyframe interval shorter than one (a pair would hold no reading of its
  /// own). In words naming the key, the measured spacing and the value to set; empty: none.
  std::string configurationConflict() const;
  const CollectorOptions& options() const { return options_; }

private:
  /// The keyframe rule shared by scans and sensor poses, for an input at stamp_s: the first
  /// input becomes the keyframe; a scan less than keyframes.interval_s minus half the input
  /// period (the gap since the previous input) after the keyframe waits, so that pairs last T
  /// within half a scan period; a sensor pose less than T after it waits (reachesKeyframeTime);
  /// one without an encoder window, or with too little motion after 4
  /// intervals, is rejected (counted) and becomes the new keyframe; any other is paired with the
  /// keyframe. Returns the caller's answer when the input is not paired: an empty event (wait) or
  /// start_keyframe(event) with the keyframe or rejection event; nullopt when it is to be paired,
  /// with *window the encoder samples from the keyframe to stamp_s.
  std::optional<CollectorEvent> unpairedInput(
      double stamp_s, const std::function<CollectorEvent(CollectorEvent)>& start_keyframe,
      std::vector<EncoderSample>* window);
  /// The event of a keyframe match once it is done, with the chain folded up to its scan: a
  /// pair, or a rejection when the match failed or disagrees with the chain.
  CollectorEvent concludeKeyframeMatch(const PlicpResult& match, const MotionPair& interval) const;
  void processScan(double stamp_s, std::shared_ptr<LazyPreparedScan> prepared,
                   std::shared_ptr<LazyPreparedScan> chain_scan);
  /// Makes `stamp_s` (a scan, or a sensor pose with `T_world_sensor`) the keyframe and queues
  /// `event` (kKeyframe, a rejection or a pair), which ends the chain.
  void startKeyframe(double stamp_s, std::shared_ptr<const LazyPreparedScan> scan,
                     const Pose2& T_world_sensor, const CollectorEvent& event);
  /// Sets the scan's sweep velocity from the prior model's prediction (compensate_sweep): over
  /// each half of the sweep, linearSweepVelocity (pair_collector.cpp).
  void compensateSweep(double stamp_s, LazyPreparedScan& prepared_scan);
  /// Whether the keyframe rule considers an input at stamp_s (none yet, or one about T after
  /// the keyframe: it is paired, rejected or extended), before unpairedInput updates the input
  /// period.
  bool reachesKeyframeTime(double stamp_s) const;
  /// Whether the scan at stamp_s joins the consecutive-scan chain (consecutive_min_spacing_s).
  bool joinsChain(double stamp_s) const;
  /// Submits the match of the previous scan to this one (`chain_scan`: the scan as the chain
  /// matches it, consecutive_max_rays), for the consecutive-scan chain.
  void submitConsecutiveMatch(double stamp_s, const std::shared_ptr<LazyPreparedScan>& prepared,
                              const std::shared_ptr<LazyPreparedScan>& chain_scan);
  /// Whether the keyframe match agrees with the chain of consecutive matches (within
  /// consistency_translation_m and consistency_rotation_rad); counts the scale check's sums.
  bool consistentWithChain(const PlicpResult& match) const;
  void processPose(double stamp_s, const Pose2& T_world_sensor, const Eigen::Matrix3d& covariance);
  void processReadyScans(bool all);
  /// `interval` (stamps and encoder window) as a pair of `sensor_motion` (covariance floor
  /// added, counted).
  CollectorEvent pairEvent(MotionPair interval, const Pose2& sensor_motion,
                           const Eigen::Matrix3d& covariance) const;
  CollectorEvent reject(const std::string& reason) const;
  /// Folds everything, forgets the state (reset) and queues the kRestarted event.
  void restart(const std::string& what);
  /// The events of a call: every one made so far without defer_keyframe_matches; with it, those
  /// whose matches are done (the calling thread first runs queued matches while more than a
  /// few wait).
  std::vector<CollectorEvent> takeEvents();
  /// Queues an event made now (in order after the matches still to fold); `ends_chain`: it
  /// starts a new keyframe, so the chain restarts after it.
  void queueEvent(const CollectorEvent& event, bool ends_chain);
  /// Encoder window of [start_s, end_s] (laser clock), or a reason why there is none.
  std::optional<std::vector<EncoderSample>> encoderWindow(double start_s, double end_s,
                                                          std::string* reason) const;
  Pose2 predict(const std::vector<EncoderSample>& window) const;
  /// Folds the queued results into the chain and the events, in order (pair_collector_fold.cpp):
  /// everything (waiting for the matches), or up to the last event (waiting), or the front ones
  /// whose matches are done (not waiting).
  enum class Fold
  {
    kAll,
    kThroughLastEvent,
    kDone,
  };
  void fold(Fold how) const;
  /// Folds the front entry (waits for its match).
  void foldFront() const;
  /// Whether the predicted motion over `window` is below the minimum motion (always false when
  /// the minimum is off or there is no predictor).
  bool tooLittleMotion(const std::vector<EncoderSample>& window) const;

  CollectorOptions options_;
  MotionPredictor predictor_;
  EncoderTrack track_;
  EncoderGlitchFilter glitch_filter_;
  StreamSpacing encoder_spacing_;  ///< of the accepted readings
  /// Recent glitches, each as the stamps of the accepted readings around it (encoder clock; the
  /// second is +inf until the next reading is accepted) [s]: no pair may overlap one. A run of
  /// spikes after which the counts go on (EncoderGlitchFilter::Result::continuous) leaves none.
  std::deque<std::pair<double, double>> glitch_spans_;
  // Mutable: the consecutive matches run in the background and are folded in lazily, also
  // from statistics(); the folded state is what a one-threaded run would have had.
  mutable CollectorStatistics statistics_;

  struct Keyframe
  {
    double stamp_s = 0.0;
    std::shared_ptr<const LazyPreparedScan> scan;  ///< laser source
    Pose2 T_world_sensor;                          ///< pose source
  };
  std::optional<Keyframe> keyframe_;
  std::shared_ptr<const LazyPreparedScan> previous_scan_;       ///< as the chain matches it
  std::shared_ptr<const LazyPreparedScan> previous_full_scan_;  ///< with every ray
  double previous_scan_stamp_s_ = 0.0;   ///< the previous scan, chained or not
  double previous_chain_stamp_s_ = 0.0;  ///< previous_scan_'s stamp
  mutable Pose2 chain_;                  ///< composed consecutive matches since the keyframe
  mutable bool chain_valid_ = false;
  /// What is folded in order (fold()): a consecutive match (into the chain), or an event that
  /// ends a keyframe interval or not (a keyframe match's, made once it is done, or one made
  /// without a match), oldest first.
  struct Unfolded
  {
    std::shared_ptr<MatchJob> consecutive;  ///< a consecutive match, or null
    std::shared_ptr<MatchJob> keyframe;     ///< a keyframe match, or null: `event` as it is
    /// The event, or with `keyframe` the interval (stamps, encoder window) it would pair.
    CollectorEvent event;
    bool ends_chain = false;
  };
  mutable std::deque<Unfolded> unfolded_;
  mutable std::vector<CollectorEvent> ready_;  ///< folded events not returned yet
  PlicpOptions consecutive_options_;           ///< options_.plicp without the unused covariance
  /// With defer_keyframe_matches, the calling thread runs queued matches itself while more than
  /// this many wait (the background thread runs the rest) [matches].
  static constexpr std::size_t kMaxQueuedMatches = 8;
  std::unique_ptr<MatchQueue> matches_;  ///< last member: its worker stops first
  double last_input_stamp_s_ = -1e300;   ///< newest stamp of any stream
  double last_scan_stamp_s_ = -1e300;    ///< newest scan / sensor pose stamp
  /// Stamp of the previous scan / sensor pose put to the keyframe rule: the input period [s].
  double previous_keyframe_input_s_ = 0.0;
  /// A scan or a sensor pose waiting for the encoder stream to reach its time.
  struct PendingInput
  {
    double stamp_s;
    std::shared_ptr<LazyPreparedScan> scan;  ///< null for a sensor pose
    /// The scan as the consecutive chain matches it: every consecutive_max_rays-th ray (the
    /// same object as `scan` at stride 1).
    std::shared_ptr<LazyPreparedScan> chain_scan;
    Pose2 T_world_sensor;
    Eigen::Matrix3d covariance;
  };
  std::deque<PendingInput> pending_;
};

}  // namespace odometry_calibration
