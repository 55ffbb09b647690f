// The calibration session of a configuration's ego-motion sources (`ego_motion.sources`,
// e.g. a front and a rear laser), free of ROS: one CalibrationSession per source (its own pair
// collector, consistency checks, time offset, pairs file, guidance), all fed the same encoder
// track; a fit fits each source alone and then the wheels and every source's pose jointly
// (calibration/joint_source_fit.h, the same function calibrate_bag calls), and every source's
// session adopts its view of the joint fit (the joint wheels, its own pose and time offset).
// With several sources one health monitor watches the joint calibration (SessionAssistant's
// several-sensor form: each source's pairs scored against its view of it, the wheels shared, so
// that an alarm names the laser that moved or the wheels); the sources' own sessions do not
// monitor. With one source it is that source's CalibrationSession unchanged: the same options,
// files, messages and fits as before.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/calibration/joint_source_fit.h"
#include "odometry_calibration/session/calibration_session.h"
#include "odometry_calibration/session/gyro_heading_odometry.h"
#include "odometry_calibration/session/gyro_health.h"
#include "odometry_calibration/session/gyro_source.h"
#include "odometry_calibration/session/wheel_signals.h"
#include "odometry_calibration/session/wheel_topic_watch.h"

namespace odometry_calibration {

/// What a fit of several sources gave besides the outcome.
struct JointCalibrateOutcome
{
  /// success, message; `fit`: the first sensor's view of the joint fit (one source: the fit).
  CalibrateOutcome outcome;
  std::optional<JointFitReport> joint;  ///< the joint fit, when one ran
  std::string text;                     ///< its tables in words (formatJointFitReport)
  /// Several sources: each source's fit alone (all of them, or none when one could not run),
  /// and what the joint fit took from them (also when it then failed).
  std::vector<SessionFit> alone;
  std::vector<JointSourceInput> inputs;
  std::string joint_failure;  ///< why the joint fit itself failed ("" when it ran)
  /// With gyro.topic: the gyro's fit against the first source's fitted pairs (gyro_fit.h), when
  /// a fit of the wheels ran.
  std::optional<GyroFit> gyro;
};

/// The joint fit of the sources' fits alone (fitSourcesJointly's signature; a test forces a
/// failure through it).
using JointFitFunction =
    std::function<JointFitReport(const CalibrationConfig&, const std::vector<JointSourceInput>&)>;

class JointCalibrationSession
{
public:
  /// One session per source of egoMotionSources(config). With several: source k's
  /// configuration is configForSource(config, k); its options are `options` with the
  /// output directory <output_directory>/source_<k> (pairs.csv, its result.yaml: the joint
  /// wheels and its pose, loaded on the next start), its topic as the ego-motion input's name,
  /// its frame (or "<default_sensor_frame>_<k>") until its messages name theirs, adopt_fits
  /// off (the joint fit is adopted), the odometry only in source 0's session, and its log lines
  /// starting with "[<topic>] ".
  /// `listener(k)`: source k's listener; `fit_jointly`: the joint fit. Throws as
  /// CalibrationSession's constructor, std::invalid_argument for several sources of a model
  /// without a joint fit, and std::runtime_error for a cloud source in a build without PCL
  /// (scan/pcl_support.h).
  JointCalibrationSession(const CalibrationConfig& config, const std::string& config_text,
                          const std::string& config_source, const SessionOptions& options,
                          const std::function<SessionListener(std::size_t)>& listener = {},
                          JointFitFunction fit_jointly = fitSourcesJointly);
  ~JointCalibrationSession();
  JointCalibrationSession(const JointCalibrationSession&) = delete;
  JointCalibrationSession& operator=(const JointCalibrationSession&) = delete;

  /// One line for the start: the wheel input, the ego-motion topics (SessionOptions::topics,
  /// or every source's), the keyframe interval, the time offset and the output folder.
  std::string startSummary() const;

  std::size_t sourceCount() const { return sessions_.size(); }
  /// Source `index`'s session (its ego-motion inputs go there); throws std::out_of_range.
  CalibrationSession& source(std::size_t index) { return *sessions_.at(index); }
  const CalibrationSession& source(std::size_t index) const { return *sessions_.at(index); }
  /// Source `index` as configured (topic, type, frame, time offset, pose).
  const EgoMotionSourceConfig& sourceConfig(std::size_t index) const { return sources_.at(index); }

  /// The encoders into every source's session (the same track for all).
  void addJointPositions(double stamp_s, const Eigen::VectorXd& raw,
                         const std::string& publisher = "");
  void skipJointState(const std::string& problem, const std::string& publisher = "");
  /// wheels.source ticks: joint `wheel`'s raw reading at `stamp_s` (wheel_signals.h); the
  /// joint samples it completes go to addJointPositions with the first joint's publisher, a
  /// reading that cannot be used to skipJointState with the reason.
  void addWheelTick(std::size_t wheel, double stamp_s, double raw,
                    const std::string& publisher = "");
  /// wheels.source joint_velocity: the joints' velocities at `stamp_s`, integrated (as above).
  void addJointVelocities(double stamp_s, const Eigen::VectorXd& velocity,
                          const std::string& publisher = "");
  /// wheels.source odometry: the base's own pose `T_odom_base` at `stamp_s`, made its path and
  /// heading joints (as above).
  void addBaseOdometry(double stamp_s, const Pose2& T_odom_base, const std::string& publisher = "");
  /// gyro.topic: one IMU reading (GyroSource::add; `angular_velocity` x, y, z [rad/s]); "" when
  /// kept, else why it was refused. `problem` non-empty: a message that could not be read,
  /// refused and counted with that reason. Without a gyro configured: refused, naming gyro.topic.
  std::string addGyroReading(double stamp_s, const Eigen::VectorXd& angular_velocity,
                             const std::string& problem = "");
  /// The gyro's readings (null without gyro.topic).
  const GyroSource* gyro() const { return gyro_.get(); }
  void flush();
  /// Every source's tick(); with wheels.source ticks also a warning (the log) per wheel topic
  /// silent beyond silent_topic_timeout_s while another wheel's publishes (wheel_topic_watch.h).
  void tick();
  /// Every source's pairs not yet written; returns how many still are not, in all.
  std::size_t writePendingPairs();

  /// The guidance marker: one source's; several: each source's text on its own line after its
  /// topic, an alarm when any source's monitor has one, ready when every source is.
  AssistantMarker assistantMarker() const;
  /// The health monitor's largest statistic (none when it does not watch).
  std::optional<double> healthStatistic() const;
  /// Several sources: the joint health monitor's status ("calibration health"), none before it
  /// watches a calibration; one source: none (its session reports its own). With a gyro fit
  /// watched, then the "gyro health" status (gyro_health.h).
  std::vector<SessionStatusReport> jointStatusReports() const;

  /// One source: its session's calibrate(). Several: each source fitted alone (a source whose
  /// fit cannot run, named by its topic, stops the call; as in calibrate_bag, one that did not
  /// converge does not), then jointly; the joint fit converged, each source's session adopts
  /// its view of it, all or none (every view prepared, then committed, the committed ones put
  /// back when one fails: the reply names the source, the previous calibration stays active in
  /// every source; with SessionOptions::adopt_fits off, as calibrate_bag's, none adopts it: the
  /// fit is the result). request.model: a model with a joint fit (jointFitModelProblem; empty: the
  /// configuration's); request.options: only that model's section, without sensor_pose (each
  /// source starts from its own), else refused naming the option.
  JointCalibrateOutcome calibrate(const CalibrationRequest& request);
  /// One source: its session's save(). Several: every source's files (CalibrationSession::
  /// filesToSave, under source_<k>/), result.yaml (jointResultYaml), laser_joints.urdf (one
  /// joint per sensor), controller.yaml (diff_drive, skid_steer, mecanum) and joint_report.txt
  /// in the output directory, as one set (common/staged_file_set.h): all replaced or, when one
  /// cannot be written (named in the reply), none.
  std::pair<bool, std::string> save();
  /// Every source's reset(), in words.
  std::pair<bool, std::string> reset();

private:
  /// Seconds on the wall clock (options' wall_clock, else the steady clock).
  double wallNow() const;
  JointCalibrateOutcome calibrateJointly(const CalibrationRequest& request);
  /// With a gyro: its fit against the first source's fitted pairs into `result` (and its line
  /// appended to the reply's message).
  void fitGyro(JointCalibrateOutcome* result);
  /// One source with a gyro fit: its session's files and the gyro in result.yaml, as one set.
  std::pair<bool, std::string> saveWithGyro() const;
  /// The joint fit's configuration: model `name` (one with a joint fit) with the call's
  /// `options`; throws std::invalid_argument naming an option it does not take or what the
  /// configuration lacks for that model.
  CalibrationConfig jointModelConfig(const std::string& name, const std::string& options) const;
  /// Each source's fit alone of joint_config's model (its own start pose); nullopt with
  /// `failure` set when one could not be fitted.
  std::optional<std::vector<SessionFit>> fitSourcesAlone(const CalibrationRequest& request,
                                                         const CalibrationConfig& joint_config,
                                                         std::size_t* pairs_collected,
                                                         std::string* failure);
  /// The joint fit of result->alone into `result` (false: result's message says why).
  bool fitJointly(const CalibrationConfig& joint_config, JointCalibrateOutcome* result);
  /// Every source adopts its view of `joint`, all or none; the reply's message.
  std::string adoptJointFit(const CalibrationConfig& joint_config, const JointFitReport& joint,
                            const std::vector<SessionFit>& fits, bool* success);
  std::string saveJoint() const;
  /// Source 0's `listener` with the gyro's wrappers: its pairs to the gyro's watch, its
  /// odometry turned by the gyro (gyro.odom_heading).
  SessionListener withGyro(SessionListener listener);
  /// An odometry listener handing `forward` the state with its heading from the gyro.
  std::function<void(const OdometryState&)> gyroHeadingOdometry(
      std::function<void(const OdometryState&)> forward);
  /// A pair listener feeding the gyro's watch, then `forward` (when set).
  std::function<void(const MotionPair&)> gyroWatchingPairs(
      std::function<void(const MotionPair&)> forward);
  /// Source `source`'s new pair into the joint monitor.
  void monitorPair(const MotionPair& pair, std::size_t source);
  /// The joint monitor watches `models` (one per source) from now on.
  void watchJointly(const std::vector<std::shared_ptr<const MotionModel>>& models,
                    const std::string& origin);
  /// The joint monitor watches the sources' saved calibrations when every source loaded one.
  void watchSavedCalibrations();

  /// A wheel message's output into the sessions (its samples, then its problem, if any).
  void feedWheelOutput(const WheelSignalOutput& output, const std::string& publisher);

  CalibrationConfig config_;
  std::string config_text_, config_source_;
  std::unique_ptr<WheelSignals> wheel_signals_;
  /// wheels.source ticks: each wheel topic's silence, said by tick() (null otherwise).
  std::unique_ptr<WheelTopicWatch> wheel_watch_;
  std::unique_ptr<GyroSource> gyro_;  ///< gyro.topic's readings; null without one
  /// The last ~calibrate's gyro fit (save() writes it into result.yaml); guarded by fit_mutex_.
  std::optional<GyroFit> gyro_fit_;
  /// With a gyro: the watch of the last ~calibrate's gyro fit, fed the readings and source 0's
  /// pairs (declared before sessions_, whose pair listener feeds it, so that it outlives them).
  std::unique_ptr<GyroHealth> gyro_health_;
  /// gyro.odom_heading (with SessionOptions::odometry): source 0's odometry with its heading
  /// from the last gyro fit that succeeded (declared before sessions_, whose odometry listener
  /// uses it); null otherwise.
  std::unique_ptr<GyroHeadingOdometry> gyro_heading_;
  std::mutex wheel_mutex_;       ///< guards wheel_signals_ and the order its samples are fed in
  std::string wheel_publisher_;  ///< the first joint's topic's publisher (ticks)
  SessionOptions options_;
  std::vector<EgoMotionSourceConfig> sources_;
  /// Several sources: the health monitor of the joint calibration (no guidance: the sources'
  /// sessions give theirs); null when the configuration turns the monitor off. Declared before
  /// sessions_ so that it outlives them: their pair listeners call monitorPair (which uses it
  /// and monitor_mutex_) until they are destroyed.
  std::unique_ptr<SessionAssistant> monitor_;
  mutable std::mutex monitor_mutex_;  ///< monitor_'s state; never held while calling a session
  std::vector<std::unique_ptr<CalibrationSession>> sessions_;
  JointFitFunction fit_jointly_;
  std::mutex fit_mutex_;  ///< calibrate(), save(), reset(): one at a time
  /// The last converged joint fit and its configuration (the call's model), for save().
  std::optional<JointFitReport> joint_;
  CalibrationConfig joint_config_;
  std::vector<JointSourceInput> joint_inputs_;
  std::string joint_text_;
};

}  // namespace odometry_calibration
