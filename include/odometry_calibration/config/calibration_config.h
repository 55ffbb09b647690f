// The one configuration of a calibration run, shared by the live node and the bag tool:
// read from YAML (config/*.yaml document every key), validated in one place with messages
// that name the key.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/scan/cloud_to_scan_options.h"

namespace odometry_calibration {

/// One joint of the JointState stream.
struct JointConfig
{
  std::string name;                              ///< joint name in sensor_msgs/JointState
  EncoderKind kind = EncoderKind::kIncremental;  ///< incremental (wheel) or absolute (steering)
  /// Units of `position` per joint turn: 2000 for a 2000-tick wheel encoder reported in ticks,
  /// 6.283185 (2 pi) for positions in radians.
  double units_per_turn = 2.0 * M_PI;
  /// Incremental: the raw counter wraps after 2^counter_bits units (0 = never wraps).
  int counter_bits = 0;
  /// Incremental: the fastest the joint can turn [turns/s]; a larger increment between two
  /// readings is an encoder glitch, skipped (encoder_glitch_filter.h). 0 = unchecked.
  double max_turns_per_s = 50.0;
  /// -1 when the joint counts backwards while the robot drives forward.
  double sign = 1.0;
};

/// What the wheels publish (`wheels.source`).
enum class WheelSource
{
  kJointState,     ///< sensor_msgs/JointState positions on joint_state_topic
  kTicks,          ///< one std_msgs number topic per joint (wheels.topics), no stamp
  kJointVelocity,  ///< sensor_msgs/JointState velocities only, integrated into positions
  kOdometry,       ///< the base's own nav_msgs/Odometry (wheels.topics[0]), three virtual joints
};

/// The std_msgs types a per-wheel tick topic may carry (`wheels.message_type`).
const std::vector<std::string>& wheelTickMessageTypes();

/// The value bits of a wheel tick type (16 for std_msgs/Int16, 53 for the floating types: their
/// exact integers), or 0 for a name not in wheelTickMessageTypes().
int wheelTickMessageBits(const std::string& type);

/// The `wheels` section: where the joints' positions come from.
struct WheelInputConfig
{
  WheelSource source = WheelSource::kJointState;
  /// ticks: one topic per joint, in the joints' order; odometry: the base's one Odometry topic.
  std::vector<std::string> topics;
  /// ticks: the topics' std_msgs type.
  std::string message_type = "std_msgs/Int32";
  /// ticks: an instant whose other wheel's samples lie further apart is dropped; joint_velocity:
  /// a longer silence restarts the integration [s].
  double max_gap_s = 0.5;
};

/// The wheel input in words for messages: "JointState on '/joint_states'", "ticks on
/// '/lwheel', '/rwheel'", "JointState velocities on '/joint_states'", "base odometry on '/odom'".
std::string wheelInputName(const WheelInputConfig& wheels, const std::string& joint_state_topic);

/// Where the sensor's ego-motion comes from.
enum class EgoMotionSource
{
  kScan,      ///< sensor_msgs/LaserScan matched with PLICP
  kOdometry,  ///< nav_msgs/Odometry of the sensor (visual odometry, another matcher)
  kPose,      ///< geometry_msgs/PoseStamped of the sensor (external tracker)
  kCloud,     ///< sensor_msgs/PointCloud2 of a 3D lidar, turned into scans (cloud_to_scan.h)
};

/// Whether the source's messages become scans matched with PLICP (scan, cloud).
inline bool matchesScans(EgoMotionSource source)
{
  return source == EgoMotionSource::kScan || source == EgoMotionSource::kCloud;
}

/// One ego-motion source of `ego_motion.sources` (several sensors, e.g. a front and a
/// rear laser, calibrated together with the wheels). Each makes its own pairs against the same
/// encoder track; the sources share the cloud, sigma, keyframe and matching keys.
struct EgoMotionSourceConfig
{
  std::string topic;                              ///< the source's messages
  EgoMotionSource type = EgoMotionSource::kScan;  ///< scan, cloud, odometry or pose
  std::string frame;  ///< the sensor's frame (base_link -> frame); "": the messages' frame
  /// Encoder values are taken at this source's stamps + this [s]; NaN: keyframes.time_offset_s.
  double time_offset_s = std::numeric_limits<double>::quiet_NaN();
  /// Start value and matcher guesses of this sensor's pose [x, y, theta] (m, m, rad); empty:
  /// the model section's sensor_pose (a rear laser needs its own: its guesses turned round).
  std::vector<double> sensor_pose;
  /// The node whose messages on `topic` are used when two publish it (empty: whichever
  /// single one does, a second is refused). Others' messages are ignored and counted.
  std::string publisher;
};

/// The IMU's gyro as a further source of the joint fit (`gyro:`; calibration/gyro_fit.h).
struct GyroConfig
{
  std::string topic;       ///< sensor_msgs/Imu topic; empty: no gyro
  double roll_rad = 0.0;   ///< the IMU's mounting roll in base_link [rad]
  double pitch_rad = 0.0;  ///< the IMU's mounting pitch in base_link [rad]
  double max_gap_s = 0.1;  ///< readings further apart: a gap no pair may span [s]
  /// ~odom's heading from the calibrated gyro, its translation from the wheels
  /// (session/gyro_heading_odometry.h); needs `topic`.
  bool odom_heading = false;
};

/// Everything a calibration run needs.
struct CalibrationConfig
{
  std::vector<JointConfig> joints;
  WheelInputConfig wheels;  ///< where the joints' positions come from
  GyroConfig gyro;          ///< the IMU's gyro (off unless gyro.topic is set)
  std::string joint_state_topic = "/joint_states";
  /// The node whose JointState messages carry the wheel joints (empty: whichever single one
  /// does; a second is refused). Others' messages are ignored and counted.
  std::string joint_state_publisher;
  EgoMotionSource ego_motion = EgoMotionSource::kScan;
  std::string scan_topic = "/scan";
  std::string ego_motion_topic;  ///< odometry / pose / cloud source topic
  /// The node whose ego-motion messages are used when two publish the topic (as
  /// joint_state_publisher; empty: one publisher only, a second is refused).
  std::string ego_motion_publisher;
  /// The key that chooses it, for messages: ego_motion.publisher, or
  /// ego_motion.sources[k].publisher in configForSource's configuration of source k of a list.
  std::string ego_motion_publisher_key = "ego_motion.publisher";
  /// A LaserScan with more rays is skipped and counted (`ego_motion.max_scan_rays`).
  long long max_scan_rays = 10000;
  CloudToScanOptions cloud;             ///< cloud source: how a cloud becomes a scan
  double ego_motion_sigma_m = 0.005;    ///< pose source: sigma of a displacement's x, y [m]
  double ego_motion_sigma_rad = 0.002;  ///< pose source: sigma of its heading [rad]
  CollectorOptions collector;           ///< keyframes, time offset, PLICP
  /// `ego_motion.sources`: several sources in one calibration; empty (the default): the one
  /// source of ego_motion.source, scan_topic and topic (egoMotionSources gives both as a list).
  std::vector<EgoMotionSourceConfig> ego_motion_sources;
  /// Estimate the encoder-laser time offset (bag tool) by searching this range [s]; the
  /// configured time_offset_s is then only the matcher's starting point.
  bool estimate_time_offset = true;
  double time_offset_search_min_s = -2.0;
  double time_offset_search_max_s = 2.0;
  /// Candidate keyframe intervals of the fitted pairs [s], increasing
  /// (`keyframes.fit_intervals_s`): the node and calibrate_bag collect pairs at each and choose one
  /// by time-blocked cross-validation on the interval_s pairs (calibration/fit_interval.h); empty:
  /// fit the interval_s pairs.
  std::vector<double> fit_intervals_s;
  std::string model = "diff_drive";         ///< model fitted by default
  std::vector<std::string> compare_models;  ///< further models fitted for the comparison table
  ModelFactoryOptions models;               ///< per-model options (joints filled in)
  /// Model used for the matcher's initial guess and the node's nominal odometry ("none", or a
  /// parametric model with its start values: "diff_drive", "tricycle", "mecanum",
  /// "skid_steer"). Also the nominal row of the comparison tables.
  std::string prior_model = "diff_drive";
  std::string output_directory = "odometry_calibration_results";
};

/// The configuration's ego-motion sources: `ego_motion.sources` with each time offset resolved,
/// or, without that list, the one source of ego_motion.source, scan_topic and topic.
std::vector<EgoMotionSourceConfig> egoMotionSources(const CalibrationConfig& config);

/// The messages of an ego-motion source of `type`, in words: "LaserScan", "PointCloud2" or
/// "pose" (an Odometry or PoseStamped).
std::string egoMessageType(EgoMotionSource type);

/// The one-source configuration of source `index` of egoMotionSources(config) (each
/// source paired on its own): its type and topic as ego_motion.source and scan_topic or topic,
/// its time offset as keyframes.time_offset_s, ego_motion.sources empty. Throws
/// std::out_of_range naming the index beyond the sources.
CalibrationConfig configForSource(const CalibrationConfig& config, std::size_t index);

/// Reads and validates a configuration. Throws std::runtime_error naming the file and the key.
CalibrationConfig loadCalibrationConfig(const std::string& path);
CalibrationConfig parseCalibrationConfig(const std::string& text, const std::string& source);

/// `config_text` with the model sections (diff_drive, tricycle, mecanum, skid_steer, linear, gp,
/// prior_model, model) replaced key by key by those of `override_yaml` (a YAML mapping, e.g.
/// "{gp: {kernel: linear}}"), then parsed and validated. Throws std::runtime_error naming a key
/// that may not be overridden or an invalid value.
CalibrationConfig overrideModelOptions(const std::string& config_text,
                                       const std::string& override_yaml, const std::string& source);

/// The configuration as it must be to fit `model` (its joints resolved and checked, e.g. a
/// tricycle's steering joint absolute), with `override_yaml` applied as above. Throws
/// std::runtime_error when the configuration cannot serve that model, saying why.
CalibrationConfig configForModel(const std::string& config_text, const std::string& model,
                                 const std::string& override_yaml, const std::string& source);

/// The checks of the `wheels` section against the joints: one topic per joint for ticks, each
/// joint's counter_bits within the message type's bits; for odometry one topic and only the
/// models that take a base odometry (base_odometry, linear, gp). Throws std::runtime_error naming
/// the key.
void validateWheelInput(const CalibrationConfig& config);

/// The joints of wheels.source odometry (models/base_odometry_model.h): base_forward and
/// base_lateral [m], base_yaw [rad], incremental, 2 pi units per "turn" (so that max_turns_per_s
/// 50 allows 314 m/s and rad/s: the glitch filter judges steps, not speeds, for them).
std::vector<JointConfig> baseOdometryJoints();

/// The encoder channels of the joints (scale-free: in the message's units). With wheels.source
/// ticks or joint_velocity the positions reach the session unwrapped: no channel wraps.
std::vector<EncoderChannelOptions> encoderChannels(const CalibrationConfig& config);

/// Raw message positions in the joints' order, signs applied.
Eigen::VectorXd applySigns(const CalibrationConfig& config, const Eigen::VectorXd& positions);

/// The joints as the models see them.
JointLayout jointLayout(const CalibrationConfig& config);

/// The prior model (diff_drive, tricycle or skid_steer at the configuration's start values,
/// unfitted: it predicts the nominal robot), or nullptr for "none".
std::shared_ptr<MotionModel> priorModel(const CalibrationConfig& config);

/// The prior model's sensor pose in base_link (the configuration's start value), if any.
std::optional<Pose2> priorSensorPose(const CalibrationConfig& config);

/// The matcher's initial guess from the prior model's start values (nullptr for "none").
MotionPredictor priorPredictor(const CalibrationConfig& config);

}  // namespace odometry_calibration
