// One calibration session: everything between the inputs and a fitted model that the
// live node and calibrate_bag share, free of ROS. It takes encoder readings and ego-motion
// samples (laser scans, a 3D lidar's clouds made scans, sensor poses) with their stamps and
// frames, pairs them (pairing/pair_collector.h, and one collector per candidate fit interval),
// keeps the pairs (and their file), the encoder history for the time-offset search, the
// odometry of the nominal robot and of the active model, the live assistant; it fits on request
// (session_fit.h) and saves the result files. The node is an adapter around it (messages in,
// topics and services out), the bag tool feeds it from the bag reader: both give the same pairs
// and the same fit from the same messages. Thread-safe: inputs may arrive while a fit runs.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/report/calibration_files.h"
#include "odometry_calibration/session/encoder_watch.h"
#include "odometry_calibration/session/input_monitor.h"
#include "odometry_calibration/session/input_publishers.h"
#include "odometry_calibration/session/input_record.h"
#include "odometry_calibration/session/pairs_store.h"
#include "odometry_calibration/session/session_assistant.h"
#include "odometry_calibration/session/session_fit.h"
#include "odometry_calibration/session/session_messages.h"
#include "odometry_calibration/session/session_odometry.h"

namespace odometry_calibration {

class CandidateCollectors;

/// Why a scan of `rays` rays is refused (more than `max_rays`, ego_motion.max_scan_rays: its
/// memory and matching time are unbounded otherwise); empty when it is not. The front ends
/// check it before converting a message.
std::string scanRaysProblem(std::size_t rays, long long max_rays);

struct SessionOptions
{
  /// Where pairs.csv, last_fit.yaml, result.yaml, controller.yaml and laser_joint.urdf go;
  /// empty: nothing is written (calibrate_bag writes its own set at the end).
  std::string output_directory;
  bool load_saved_calibration = true;  ///< start from output_directory/result.yaml
  bool resume_pairs = true;            ///< continue output_directory/pairs.csv
  int min_pairs = 10;                  ///< calibrate() refuses with fewer pairs
  bool odometry = true;                ///< integrate the nominal and active model's odometry
  SessionOdometryOptions odometry_options;
  bool assistant = true;  ///< excitation guidance and health monitor
  SessionAssistantOptions assistant_options;
  /// Fit-interval candidates paired besides keyframes.interval_s (none: the config's
  /// keyframes.fit_intervals_s).
  std::optional<std::vector<double>> candidate_intervals_s;
  /// Keep every decoded encoder sample for the time-offset search (none: when the
  /// configuration estimates the offset).
  std::optional<bool> keep_encoder_history;
  bool compare_trajectories = false;  ///< the report's trajectories in each fit
  /// A converged fit becomes the active model (odometry, time offset for new pairs, monitor,
  /// last_fit.yaml); calibrate_bag: off, the fit is the result.
  bool adopt_fits = true;
  /// How the reply names the minimum pair count ("" for a tool without such a parameter).
  std::string min_pairs_name = "~min_pairs";
  std::string source = "calibration session";  ///< result.yaml's `source`
  std::string base_frame = "base_link";        ///< laser_joint.urdf's parent
  std::string default_sensor_frame = "laser";  ///< until an input names the sensor's frame
  std::array<std::string, 2> topics = {"joint states", "ego-motion"};  ///< for messages
  double silent_topic_timeout_s = 5.0;  ///< an input silent this long is warned about [s]
  std::function<double()> wall_clock;   ///< seconds on the wall clock (default: steady clock)
  SessionLog log;                       ///< what the session says (default: nothing)
};

/// What a front end needs to handle the session's events as they happen (all may be empty).
/// Called with the session's lock held: do not call back into the session.
struct SessionListener
{
  std::function<void(const MotionPair&)> pair;         ///< a new pair
  std::function<void(const OdometryState&)> odometry;  ///< new corrected odometry
  /// The sensor's pose (none: not known) or frame changed (re-send tf).
  std::function<void(const std::optional<Pose2>& T_base_sensor, const std::string& frame)>
      sensor_pose;
};

struct CalibrationRequest
{
  std::string model;    ///< empty: the configuration's `model`
  std::string options;  ///< YAML overriding the configuration's model sections ("" none)
  /// Default: kChoose when there are candidate intervals, else kConfigured.
  std::optional<FitIntervalMode> interval_mode;
  double fixed_interval_s = 0.0;  ///< with kFixed [s]
  /// With kChoose: the cuts of the cross-validation (FitIntervalOptions::fold_counts; empty:
  /// its default).
  std::vector<std::size_t> fold_counts;
  double fit_until_stamp_s = INFINITY;  ///< fit only pairs ending by this stamp
  /// Hold out the last pairs (data/holdout.h: holdOutLastPairs of the pairs fitted, after any
  /// pairing at the estimated offset): fit only those before its border (calibrate_bag
  /// --holdout). In (0, 1); none: fit_until_stamp_s.
  std::optional<double> holdout_fraction;
  /// After a successful fit on all pairs, the reply's held-out table (held_out_comparison.h):
  /// every model refitted on the pairs before the last fraction and scored on that fraction
  /// (the live node's ~holdout_fraction). In [0, 1); 0: none.
  double reply_holdout_fraction = 0.0;
  std::optional<TimeOffsetResult> offset_search;  ///< already run on exactly these pairs
  /// The model sections for `model`, configured already (a joint session's, each source's
  /// with its own start pose): `options` is then not read.
  std::optional<ModelFactoryOptions> models;
};

struct CalibrateOutcome
{
  bool success = false;           ///< a converged fit that is now the active model
  std::string message;            ///< what happened or what to do, in words
  std::optional<SessionFit> fit;  ///< the fit, when one ran (also when it did not converge)
  std::size_t pairs_collected = 0;
};

/// The stamps of one input's messages (used or skipped after their stamp was read): how many,
/// the first, and whether any other differed from it. A publisher that does not stamp its
/// messages sends them all with one stamp (often 0, or the time it started).
struct InputStamps
{
  std::size_t count = 0;
  double first_s = 0.0;
  bool varied = false;

  void add(double stamp_s)
  {
    if (count++ == 0)
      first_s = stamp_s;
    else if (stamp_s != first_s)
      varied = true;
  }
  /// Ten or more messages, every one at the same stamp (fewer are not yet evidence of a
  /// publisher that does not stamp: a few bad messages may share one).
  bool oneStamp() const { return count >= 10 && !varied; }
};

/// The session's counts and state, for /diagnostics and summaries.
struct SessionCounts
{
  CollectorStatistics statistics;
  std::size_t pairs = 0, pairs_resumed = 0, pairs_unwritten = 0;
  std::size_t encoder_messages = 0, ego_messages = 0;  ///< received (used or not)
  InputStamps encoder_stamps, ego_stamps;              ///< the stamps of the messages with data
  std::size_t bad_encoder_messages = 0, bad_ego_messages = 0, clouds_without_times = 0;
  std::string first_bad_encoder_message, first_bad_ego_message, first_cloud_time_problem;
  std::vector<std::string> restarts;  ///< time going backwards, in words (the first 100)
  std::size_t restart_count = 0;      ///< every restart
  /// Two publishers of one input with none chosen (input_publishers.h), in words; empty: none.
  std::string publisher_conflict;
  /// A configured value the data contradicts (PairCollector::configurationConflict), in words
  /// naming the key, the measured value and the value to set; empty: none.
  std::string configuration_conflict;
  /// Messages from another publisher than the one used (ignored; refused after a conflict).
  std::size_t ignored_encoder_messages = 0, ignored_ego_messages = 0;
  std::string encoder_publisher;          ///< whose JointStates are used ("" before any)
  std::string ignored_encoder_publisher;  ///< the first other publisher ("" without one)
  std::string ego_publisher;              ///< whose ego-motion messages are used ("" before any)
  std::string ignored_ego_publisher;      ///< the first other publisher ("" without one)
};

/// A fit made ready to become a session's active model (CalibrationSession::prepareAdoption);
/// once committed, it holds the state it replaced, so that rollBackAdoption can put it back.
class PreparedAdoption
{
public:
  PreparedAdoption();
  PreparedAdoption(PreparedAdoption&&) noexcept;
  PreparedAdoption& operator=(PreparedAdoption&&) noexcept;
  ~PreparedAdoption();

private:
  friend class CalibrationSession;
  struct State;
  std::unique_ptr<State> state_;
};

class CalibrationSession
{
public:
  /// The last adopted fit's pair counts, as its reply and report give them (for /diagnostics).
  struct FitCounts
  {
    std::size_t used = 0, rejected = 0, down_weighted = 0;
  };

  /// `config` as parsed from `config_text` (read from `config_source`, for messages). Loads the
  /// saved calibration and resumes the pairs file as the options say. Throws
  /// std::invalid_argument / std::runtime_error for options or files it cannot use.
  CalibrationSession(const CalibrationConfig& config, const std::string& config_text,
                     const std::string& config_source, SessionOptions options,
                     SessionListener listener = {});
  ~CalibrationSession();
  CalibrationSession(const CalibrationSession&) = delete;
  CalibrationSession& operator=(const CalibrationSession&) = delete;

  // --- Inputs (calibration_session_inputs.cpp) ---
  // Each input names its `publisher` (a bag connection's callerid, a live message's publisher;
  // "" when unknown): a second publisher of one input is refused, or ignored when the
  // configuration chooses one (input_publishers.h).
  /// The configured joints' positions (encoderChannels order, signs applied) at `stamp_s`.
  void addJointPositions(double stamp_s, const Eigen::VectorXd& raw,
                         const std::string& publisher = "");
  /// A JointState that could not be read (`problem` says why): counted and warned.
  void skipJointState(const std::string& problem, const std::string& publisher = "");
  /// A laser scan in `frame` (empty: unnamed). A scan with fewer usable readings than
  /// scan_matching.min_points is skipped and counted.
  void addScan(double stamp_s, const Scan& scan, const std::string& frame,
               const std::string& publisher = "");
  /// A 3D lidar's cloud made a scan: the first cloud's frame is the sensor's, a cloud in
  /// another is skipped; `time_problem` non-empty: used without its per-point times.
  void addCloudScan(double stamp_s, const Scan& scan, const std::string& frame,
                    const std::string& time_problem, const std::string& publisher = "");
  /// An ego-motion message that gave nothing (`what`: its type, `problem`: why).
  void skipEgoMessage(const std::string& what, const std::string& problem,
                      const std::string& publisher = "");
  /// The sensor's pose from another tool (odometry, pose); `frame` its child frame (or empty).
  void addSensorPose(double stamp_s, const Pose2& T_world_sensor, const std::string& frame,
                     const std::string& publisher = "");
  /// The end of the data: scans waiting for their encoders are paired now (with what the
  /// encoders gave). calibrate_bag calls it at the end of the bags; the node's input ends
  /// when every input has been silent for silent_topic_timeout_s (tick(), calibrate()).
  void flush();
  /// Periodic work: silent-input warnings, pairs the disk did not take, and the end of the
  /// input: every input silent for silent_topic_timeout_s after input came completes the
  /// waiting pairs (flush(), once per silence).
  void tick();
  /// Writes the pairs the disk did not take yet; returns how many still are not written.
  std::size_t writePendingPairs();

  // --- Queries ---
  std::vector<MotionPair> pairs() const;
  std::vector<IntervalPairs> candidatePairs() const;
  std::vector<EncoderSample> encoderHistory() const;
  /// The memory the input record holds [bytes] (0 without one: the offset not estimated) and
  /// the bytes of scans it spilled to its scratch file.
  std::pair<std::size_t, std::uint64_t> inputRecordBytes() const;
  SessionCounts counts() const;
  /// SessionCounts::publisher_conflict alone (counts() waits for the collector's matches).
  std::string publisherConflict() const;
  /// What stops the session from calibrating, as soon as the inputs show it: the publisher
  /// conflict, else the configuration conflict; empty: none.
  std::string inputConflict() const;
  double timeOffset() const;
  std::optional<Pose2> sensorPose() const;
  std::string sensorFrame() const;
  bool hasNominalOdometry() const;
  /// The paths (the scan-matched one drawn through the known or configured sensor pose).
  OdometryPaths paths() const;
  /// What went wrong with the inputs so far, in words, one line each: messages ignored from
  /// another publisher, skipped JointStates and ego-motion messages (how many, the first
  /// reason), clouds used without their per-point times, encoder glitches per joint, restarts
  /// after time went backwards; empty for a clean collection.
  std::vector<std::string> collectionNotes() const;
  /// "calibration", "excitation guidance", "calibration health" (those that exist);
  /// input rates over `period_s`.
  std::vector<SessionStatusReport> statusReports(double period_s);
  AssistantMarker assistantMarker() const;
  std::optional<double> healthStatistic() const;  ///< none when nothing is watched
  /// The active model (none before any) and what it is ("nominal ..." for the configuration's
  /// own values, else a fit or a saved calibration): for a monitor outside the session.
  std::pair<std::shared_ptr<const MotionModel>, std::string> activeModel() const;

  // --- Actions (calibration_session_actions.cpp) ---
  /// Fits (session_fit.h) the pairs held at the call (the waiting ones completed first when the
  /// input has ended, as tick() would). When the configuration estimates the time offset and
  /// the estimate on these pairs differs from the offset they were paired at by more than
  /// kOffsetPairingToleranceS, the recorded inputs are paired again at the estimate (fresh
  /// collectors, as a session configured at it would have paired them), those pairs (also the
  /// candidates' and the encoder history) are fitted and become the session's (pairs.csv
  /// rewritten; new pairs are made at the estimate); the fit's offset_pairing says what was
  /// done. A converged fit becomes the active model
  /// (odometry integrated again, health monitor, guidance recentred, new time offset for new
  /// pairs) and is written to last_fit.yaml.
  CalibrateOutcome calibrate(const CalibrationRequest& request);
  // A fit made elsewhere (one sensor's view of a joint fit of several sources) made the active
  // model as calibrate() does with a converged fit of its own, also with adopt_fits off; in
  // steps, for a caller that adopts fits in several sessions all or none
  // (joint_calibration_session.h): prepare each session's, commit each (rolling back the
  // committed ones when one fails), then finish each.
  /// `fit` of model `name` (configured as `models`: the call's model and options) made ready to
  /// become the active model: its result file's text, its odometry integrated again, the
  /// pairing at its time offset; the session is unchanged. Throws std::invalid_argument for a
  /// fit that did not converge, std::runtime_error saying what else failed (its odometry).
  PreparedAdoption prepareAdoption(const SessionFit& fit, const std::string& name,
                                   const ModelFactoryOptions& models);
  /// The prepared fit becomes the active model (model, sensor pose told to the listener, time
  /// offset for new pairs, odometry). When the listener throws (or the odometry cannot take
  /// the newest samples), the session is put back as it was and the exception passed on.
  /// Throws std::logic_error for an adoption not prepared or committed already.
  void commitAdoption(PreparedAdoption& adoption);
  /// Puts back the state a committed adoption replaced (the listener told the previous pose;
  /// what it throws then is logged). The odometry runs on from where it was, also when the
  /// fit's time offset had restarted it (the samples between commit and roll-back are taken
  /// as one step).
  void rollBackAdoption(PreparedAdoption& adoption);
  /// The rest of a committed adoption: last_fit.yaml, the guidance recentred, the health
  /// monitor watching, the time offset's log line; the outcome as calibrate() gives it.
  /// Throws std::logic_error for an adoption not committed.
  CalibrateOutcome finishAdoption(PreparedAdoption& adoption, std::size_t pairs_collected);
  /// What save() writes now (report/calibration_files.h: result.yaml, controller.yaml or its
  /// removal, laser_joint.urdf with a sensor pose); throws std::runtime_error when there is
  /// nothing to save.
  FileSet filesToSave() const;
  /// Writes the last successful fit: result.yaml, controller.yaml (diff_drive, skid_steer,
  /// mecanum), laser_joint.urdf (with a sensor pose). Returns {success, message}.
  std::pair<bool, std::string> save();
  /// A new collection: pairs set aside, pairing, odometry, history and guidance restarted; the
  /// active model stays. Returns {success, what was done in words}; when the pairs file cannot
  /// be moved aside nothing is reset.
  std::pair<bool, std::string> reset();

private:
  void loadSavedCalibration();
  void startOdometry();
  void makeCollectors();
  void handleEvents(const std::vector<CollectorEvent>& events, double stamp_s);
  void recordEncoderHistory(double stamp_s, const Eigen::VectorXd& accepted);
  void integrate(double stamp_s, const Eigen::VectorXd& accepted);
  /// The scan into the collectors (their events); throws std::invalid_argument for a scan
  /// with too few usable readings or one the collector refuses.
  std::vector<CollectorEvent> takeScan(double stamp_s, const Scan& scan);
  /// Time went backwards: pairing, odometry and the encoder history start again.
  void restart(const std::string& reason, double stamp_s);
  void noteFrame(const std::string& frame);
  void notifySensorPose() const;
  void warnInput(const std::string& problem, const std::string& text);
  /// "all <n> JointState samples on <topic> carry the same stamp <t> s: ..." when every
  /// message of an input came at one stamp (no pair can be made of them), else "".
  std::string oneStampProblem() const;
  /// Whether a message of `input` from `publisher` is used (counted as received either way);
  /// `carries_data`: false for one that could not be read (it names no publisher of the
  /// joints, so it starts no conflict).
  bool admit(SessionInput input, const std::string& publisher, bool carries_data = true);
  /// A message that could not be used: counted (the first one's problem kept) and warned.
  void rejectInput(SessionInput input, const std::string& what, const std::string& problem);
  void say(SessionLogLevel level, const std::string& text) const;
  double now() const;
  std::string collectionStatus(SessionStatusReport* status) const;
  /// What a fit needs, taken under the lock (and the guidance's summary for the reply; the
  /// input record as it is now and the number of resumed pairs, when asked for: a record that
  /// cannot be read is dropped, said once).
  SessionFitRequest snapshot(std::string* guidance,
                             std::optional<InputRecordView>* record = nullptr,
                             std::size_t* resumed = nullptr);
  // --- Pairing at the estimated time offset (calibration_session_offset.cpp) ---
  /// Fresh collectors and what they made of recorded inputs.
  struct PairingAgain;
  /// An input for the record (dropped, with an error said once, when it cannot be written).
  void record(const std::function<void(InputRecord&)>& add);
  /// Drops the input record after `error` (said once): no pairing again until a reset.
  void dropRecord(const std::string& error);
  void flushLocked();  ///< flush() with mutex_ held
  /// Completes the waiting pairs when every input has been silent beyond the timeout.
  void completeWhenInputEnded();
  /// Pairs `record` again at the estimate on `again`'s pairs while it moves by more than
  /// kOffsetPairingToleranceS, up to kMaxPairingRounds pairings in all (`rounds` counts them).
  std::unique_ptr<PairingAgain> pairUntilSettled(const InputRecordView& record,
                                                 const CalibrationConfig& config,
                                                 std::unique_ptr<PairingAgain> again, int* rounds);
  /// calibrate()'s pairing step (see there) on the snapshot `request` (config_'s model): the
  /// re-paired state (null when the pairs stay as they are; `pairing` says why).
  std::unique_ptr<PairingAgain> pairAtEstimatedOffset(const std::optional<InputRecordView>& record,
                                                      std::size_t resumed,
                                                      SessionFitRequest* request,
                                                      OffsetPairing* pairing);
  /// calibrate()'s fit of the snapshot `fit_request` (its model configured): the request's
  /// interval, the pairing at the estimated offset (pairAtEstimatedOffset, its pairs made the
  /// session's only when the fit converged, or always without adopt_fits), the held-out part;
  /// throws what fitSessionPairs throws.
  SessionFit fitPairs(const CalibrationRequest& request,
                      const std::optional<InputRecordView>& record, std::size_t resumed,
                      SessionFitRequest* fit_request);
  /// Fresh collectors of `options` at `offset_s` fed `record` (without the lock); null when the
  /// record cannot be read back (dropped; `problem` says so).
  std::unique_ptr<PairingAgain> pairRecord(const InputRecordView& record, CollectorOptions options,
                                           double offset_s, std::string* problem);
  /// Feeds `inputs` to `again`'s collectors as the session feeds its own.
  void feed(const InputRecordView& inputs, PairingAgain* again) const;
  /// The record's inputs since `first`, under the lock (none when it was dropped or cannot be
  /// read: then dropped).
  std::optional<InputRecordView> recordSince(std::size_t first);
  /// The re-paired collectors, pairs and history, fed the inputs recorded since the snapshot
  /// (mostly without the lock, the last of them under it), become the session's, at their
  /// offset. False (nothing changed) when the record was dropped meanwhile.
  bool install(PairingAgain* again);
  /// `config`'s model sections for model `name` with the call's `options` (or its `models`);
  /// throws naming why.
  void configureModel(const std::string& name, const CalibrationRequest& request,
                      CalibrationConfig* config) const;
  /// A converged fit becomes the active model; the outcome's message says what happened.
  void adopt(const std::string& name, const CalibrationConfig& config, const std::string& guidance,
             CalibrateOutcome* outcome);
  // The steps of adopt() (the public ones take fit_mutex_ first).
  PreparedAdoption prepare(const SessionFit& fit, const std::string& name,
                           const CalibrationConfig& config, const std::string& guidance) const;
  void commit(PreparedAdoption& adoption);
  void rollBack(PreparedAdoption& adoption);  ///< with mutex_ held
  CalibrateOutcome finish(PreparedAdoption& adoption, std::size_t pairs_collected);
  /// Exchanges the active model's state with `adoption`'s; throws (nothing exchanged) what the
  /// odometry's catch-up throws. Called with mutex_ held.
  void exchangeActive(PreparedAdoption& adoption);
  /// The pair collectors of `options` (and the fit-interval candidates' ones).
  void buildCollectors(const CollectorOptions& options, std::unique_ptr<PairCollector>* collector,
                       std::unique_ptr<CandidateCollectors>* candidates) const;
  /// The corrected odometry integrated again with the fit (empty without odometry).
  OdometryReplay replayOdometry(const SessionFit& fit) const;
  /// The sensor pose after `fit`: its own, or the one known before.
  std::optional<Pose2> fitSensorPose(const SessionFit& fit) const;
  std::string successMessage(const std::string& name, const SessionFit& fit) const;

  mutable std::mutex mutex_;  ///< the state; inputs, queries and the fit's start and end
  std::mutex fit_mutex_;      ///< held by calibrate() and reset(): taken before mutex_
  CalibrationConfig config_;
  std::string config_text_, config_source_;
  SessionOptions options_;
  SessionListener listener_;
  std::vector<EncoderChannelOptions> channels_;
  std::unique_ptr<PairCollector> collector_;
  std::unique_ptr<CandidateCollectors> candidates_;
  std::vector<double> candidate_intervals_s_;
  std::unique_ptr<PairsStore> store_;
  bool keep_history_ = false;
  bool history_broken_ = false;  ///< time went backwards: no continuous stream until reset
  std::unique_ptr<EncoderDecoder> history_decoder_;
  std::vector<EncoderSample> encoder_history_;
  /// The collectors' inputs, when the configuration estimates the time offset (input_record.h).
  std::unique_ptr<InputRecord> record_;
  bool input_since_flush_ = false;  ///< inputs came since the last flush (or the start)
  std::unique_ptr<SessionOdometry> odometry_;
  std::unique_ptr<SessionAssistant> assistant_;
  std::unique_ptr<InputMonitor> inputs_;
  std::unique_ptr<InputPublishers> publishers_;
  std::unique_ptr<EncoderWatch> encoder_watch_;  ///< stuck or glitching encoders, for the status
  std::shared_ptr<const MotionModel> active_model_;
  std::string active_model_origin_;
  double model_interval_s_ = 0.5;  ///< window of the active model's predictions [s]
  std::shared_ptr<const MotionModel> fitted_model_;  ///< last successful fit (for save())
  FileSet fitted_files_;  ///< the last successful fit's files (calibrationFiles)
  std::optional<FitCounts> last_fit_counts_;
  std::optional<Pose2> T_base_sensor_;  ///< learned (or saved) sensor pose
  std::string sensor_frame_;            ///< from the inputs' headers
  bool cloud_frame_fixed_ = false;      ///< the first cloud fixed the frame
  bool has_nominal_ = false;            ///< the nominal robot's odometry runs
  SessionCounts counts_;
  std::string last_problem_;
  std::set<std::string> rejection_reasons_seen_;
};

}  // namespace odometry_calibration
