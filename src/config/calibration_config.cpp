// Reads a calibration configuration from its schema (calibration_config_schema.h): duplicated
// and unknown keys refused, every key read and range-checked as declared (its default when
// absent), then the checks across keys and the models' joints resolved.
#include "odometry_calibration/config/calibration_config.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/config_schema.h"
#include "odometry_calibration/common/name_list.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/config/calibration_config_schema.h"

#include "odometry_calibration/gp/gp_options.h"

namespace odometry_calibration {
namespace {

/// The values the configuration gives, by full key (the keys it leaves out are absent).
using GivenValues = std::map<std::string, ConfigValue>;

/// The string given for `key`, or `fallback`.
std::string givenString(const GivenValues& given, const std::string& key,
                        const std::string& fallback)
{
  const auto found = given.find(key);
  return found == given.end() ? fallback : std::get<std::string>(found->second);
}

/// Runs `check`, a model's or the collector's own validation, naming `section` in its error.
template <typename Check>
void inSection(const std::string& section, Check check)
{
  try {
    check();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(section + ": " + error.what());
  }
}

int jointIndex(const CalibrationConfig& config, const std::string& name, const std::string& key)
{
  for (std::size_t j = 0; j < config.joints.size(); ++j) {
    if (config.joints[j].name == name)
      return static_cast<int>(j);
  }
  std::vector<std::string> names;
  for (const auto& joint : config.joints)
    names.push_back(joint.name);
  throw std::runtime_error(key + ": no joint named '" + name + "' among 'joints' (" +
                           quotedNames(names) + ")");
}

/// The joint named by `key` (default: joint `nth`, "" when there is none).
int namedJoint(const CalibrationConfig& config, const GivenValues& given, const std::string& key,
               std::size_t nth)
{
  const std::string fallback = nth < config.joints.size() ? config.joints[nth].name : "";
  return jointIndex(config, givenString(given, key, fallback), key);
}

/// Whether the configuration fits, compares or guesses with `model`.
bool uses(const CalibrationConfig& c, const std::string& model)
{
  if (model == "diff_drive" && uses(c, "tracked"))
    return true;  // the tracked model takes the diff_drive section
  return c.model == model || c.prior_model == model ||
         std::find(c.compare_models.begin(), c.compare_models.end(), model) !=
             c.compare_models.end();
}

/// The value `config` holds for the schema's `key`.
ConfigValue schemaValue(const CalibrationConfig& config, const std::string& key)
{
  for (const auto& entry : calibrationConfigSchema()) {
    if (entry.spec.key == key)
      return entry.get(config);
  }
  throw std::logic_error("no configuration key " + key);
}

/// Every full key of the schema, for the unknown-key check.
const std::vector<std::string>& schemaKeys()
{
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const ConfigKeySpec* spec : calibrationConfigSpecs())
      all.push_back(spec->key);
    return all;
  }();
  return keys;
}

JointConfig readJoint(const YAML::Node& node, const std::string& prefix)
{
  JointConfig joint;
  for (const auto& entry : jointConfigSchema()) {
    const std::string name = entry.spec.key.substr(entry.spec.key.find("].") + 2);
    const YAML::Node value = node[name];
    if (value)
      entry.set(joint, readConfigValue(value, entry.spec, prefix + name));
    else if (entry.spec.default_value)
      entry.set(joint, *entry.spec.default_value);
    else
      throw std::runtime_error(prefix + name + ": required (" + entry.spec.description + ")");
  }
  return joint;
}

std::vector<JointConfig> readJoints(const YAML::Node& root)
{
  const YAML::Node joints = root["joints"];
  if (!joints || !joints.IsSequence() || joints.size() == 0)
    throw std::runtime_error("joints: a list of joints is required");
  constexpr std::size_t kMaxJoints = 64;
  if (joints.size() > kMaxJoints) {
    throw std::runtime_error("joints: " + std::to_string(joints.size()) +
                             " joints; allowed: 1 to " + std::to_string(kMaxJoints));
  }
  std::vector<JointConfig> result;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const std::string prefix = "joints[" + std::to_string(i) + "].";
    result.push_back(readJoint(joints[i], prefix));
    for (std::size_t j = 0; j < i; ++j) {
      if (result[j].name == result[i].name)
        throw std::runtime_error(prefix + "name: '" + result[i].name + "' names joints[" +
                                 std::to_string(j) + "] too; joint names must differ");
    }
  }
  return result;
}

/// `ego_motion.sources`, when given: each entry's keys (topic required, time_offset_s
/// left NaN when absent), distinct topics, and none of the one-source keys beside it.
/// The joints: the configuration's, or for wheels.source odometry the base odometry's own
/// (then `joints` must be left out).
std::vector<JointConfig> readJointsFor(const YAML::Node& root, WheelSource source)
{
  if (source != WheelSource::kOdometry)
    return readJoints(root);
  if (root["joints"]) {
    throw std::runtime_error(
        "joints: wheels.source odometry makes its own joints (base_forward, "
        "base_lateral, base_yaw from the base's odometry): leave joints out");
  }
  return baseOdometryJoints();
}

std::vector<EgoMotionSourceConfig> readSources(const YAML::Node& root)
{
  const YAML::Node sources = findConfigNode(root, "ego_motion.sources");
  if (!sources)
    return {};
  if (!sources.IsSequence() || sources.size() == 0 || sources.size() > 16)
    throw std::runtime_error("ego_motion.sources: a list of 1 to 16 sources is required");
  for (const char* single : {"source", "scan_topic", "topic", "publisher"}) {
    if (root["ego_motion"][single])
      throw std::runtime_error(std::string("ego_motion.") + single +
                               ": give either ego_motion.sources or the one source's keys");
  }
  std::vector<EgoMotionSourceConfig> result;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::string prefix = "ego_motion.sources[" + std::to_string(i) + "].";
    EgoMotionSourceConfig source;
    for (const auto& entry : sourceConfigSchema()) {
      const std::string name = entry.spec.key.substr(entry.spec.key.find("].") + 2);
      if (const YAML::Node value = sources[i][name])
        entry.set(source, readConfigValue(value, entry.spec, prefix + name));
      else if (entry.spec.default_value)
        entry.set(source, *entry.spec.default_value);
      else if (name == "topic")
        throw std::runtime_error(prefix + name + ": required (" + entry.spec.description + ")");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (result[j].topic == source.topic)
        throw std::runtime_error(prefix + "topic: '" + source.topic + "' is ego_motion.sources[" +
                                 std::to_string(j) + "]'s too; each source needs its own topic");
    }
    result.push_back(source);
  }
  return result;
}

/// Every other key: its value when given, else its default; the values given, by key.
GivenValues readKeys(const YAML::Node& root, CalibrationConfig* c)
{
  GivenValues given;
  for (const auto& entry : calibrationConfigSchema()) {
    const YAML::Node node = findConfigNode(root, entry.spec.key);
    if (node) {
      const ConfigValue value = readConfigValue(node, entry.spec, entry.spec.key);
      given[entry.spec.key] = value;
      if (entry.set)
        entry.set(*c, value);
    } else if (entry.set && entry.spec.default_value) {
      entry.set(*c, *entry.spec.default_value);
    }
  }
  return given;
}

/// The checks across keys of ego_motion, keyframes and scan_matching, and gyro.odom_heading.
void resolveSensor(CalibrationConfig& c)
{
  if (c.gyro.odom_heading && c.gyro.topic.empty()) {
    throw std::runtime_error(
        "gyro.odom_heading: true needs the gyro: set gyro.topic (the sensor_msgs/Imu topic) or "
        "gyro.odom_heading: false");
  }
  if (c.ego_motion != EgoMotionSource::kScan && c.ego_motion_topic.empty()) {
    throw std::runtime_error("ego_motion.topic: source '" +
                             formatConfigValue(schemaValue(c, "ego_motion.source")) +
                             "' needs 'topic'");
  }
  CloudToScanOptions& cloud = c.cloud;
  if (!(cloud.band_min_m < cloud.band_max_m)) {
    throw std::runtime_error(
        "ego_motion.cloud.band_m: " +
        formatConfigValue(std::vector<double>{cloud.band_min_m, cloud.band_max_m}) +
        ": need band_min_m < band_max_m");
  }
  if (!(cloud.range_min_m < cloud.range_max_m)) {
    throw std::runtime_error(
        "ego_motion.cloud.range_max_m: " + formatConfigValue(cloud.range_max_m) +
        " must exceed ego_motion.cloud.range_min_m (" + formatConfigValue(cloud.range_min_m) + ")");
  }
  // A cloud is rejected where its scan would be: with fewer rays than the matcher needs.
  cloud.min_points = static_cast<std::size_t>(std::max(1, c.collector.plicp.min_points));
  // The option structs' own checks (PairCollector runs the collector's again, for options not
  // read from a file); the schema's ranges are inside theirs, so on a file they only guard.
  inSection("ego_motion.cloud", [&] { validate(cloud); });
  inSection("keyframes", [&] { validate(c.collector); });
}

void resolveDiffDrive(CalibrationConfig& c, const GivenValues& given)
{
  DiffDriveOptions& d = c.models.diff_drive;
  if (!uses(c, "diff_drive"))
    return;
  d.layout.left_index = namedJoint(c, given, "diff_drive.left_joint", 0);
  d.layout.right_index = namedJoint(c, given, "diff_drive.right_joint", 1);
  const JointConfig& left = c.joints[static_cast<std::size_t>(d.layout.left_index)];
  const JointConfig& right = c.joints[static_cast<std::size_t>(d.layout.right_index)];
  if (left.units_per_turn != right.units_per_turn) {
    throw std::runtime_error("diff_drive: the two wheels need the same units_per_turn ('" +
                             left.name + "': " + formatConfigValue(left.units_per_turn) + ", '" +
                             right.name + "': " + formatConfigValue(right.units_per_turn) + ")");
  }
  d.layout.ticks_per_turn = left.units_per_turn;
  inSection("diff_drive", [&] { validate(d); });
}

void resolveTricycle(CalibrationConfig& c, const GivenValues& given)
{
  TricycleModelOptions& t = c.models.tricycle;
  if (!uses(c, "tricycle"))
    return;
  t.layout.steering_index = namedJoint(c, given, "tricycle.steering_joint", 0);
  t.layout.traction_index = namedJoint(c, given, "tricycle.traction_joint", 1);
  const JointConfig& steering = c.joints[static_cast<std::size_t>(t.layout.steering_index)];
  const JointConfig& traction = c.joints[static_cast<std::size_t>(t.layout.traction_index)];
  if (steering.kind != EncoderKind::kAbsolute || traction.kind != EncoderKind::kIncremental) {
    const bool steering_wrong = steering.kind != EncoderKind::kAbsolute;
    const JointConfig& wrong = steering_wrong ? steering : traction;
    throw std::runtime_error(
        std::string("tricycle.") + (steering_wrong ? "steering_joint" : "traction_joint") + ": '" +
        wrong.name + "' is kind: " + (steering_wrong ? "incremental" : "absolute") +
        "; the steering joint must be kind: absolute and the traction joint "
        "incremental");
  }
  t.layout.steering_ticks_per_turn = steering.units_per_turn;
  t.layout.traction_ticks_per_turn = traction.units_per_turn;
  inSection("tricycle", [&] {
    validate(t.calibration);
    validateStartValues(t.initial);
  });
}

void resolveMecanum(CalibrationConfig& c, const GivenValues& given)
{
  MecanumOptions& m = c.models.mecanum;
  const auto radii = given.find("mecanum.wheel_radii_m");
  if (radii != given.end()) {
    const auto& values = std::get<std::vector<double>>(radii->second);
    std::copy(values.begin(), values.end(), m.initial_radius_m.begin());
  }
  if (!uses(c, "mecanum"))
    return;
  if (c.joints.size() < 4)
    throw std::runtime_error("mecanum: needs four wheel joints among 'joints'");
  const char* keys[4] = {"mecanum.front_left_joint", "mecanum.front_right_joint",
                         "mecanum.rear_left_joint", "mecanum.rear_right_joint"};
  int* index[4] = {&m.layout.front_left_index, &m.layout.front_right_index,
                   &m.layout.rear_left_index, &m.layout.rear_right_index};
  for (std::size_t i = 0; i < 4; ++i) {
    *index[i] = namedJoint(c, given, keys[i], i);
    const JointConfig& joint = c.joints[static_cast<std::size_t>(*index[i])];
    if (joint.kind != EncoderKind::kIncremental)
      throw std::runtime_error(std::string(keys[i]) + ": '" + joint.name +
                               "' must be kind: incremental");
    if (joint.units_per_turn != c.joints[static_cast<std::size_t>(*index[0])].units_per_turn)
      throw std::runtime_error("mecanum: the four wheels need the same units_per_turn");
  }
  m.layout.ticks_per_turn = c.joints[static_cast<std::size_t>(*index[0])].units_per_turn;
  inSection("mecanum", [&] { validate(m); });
}

/// A skid-steer side's joints: given, or the incremental joints whose names contain `word`
/// ("left", or "right" without "left").
std::vector<int> skidSteerSide(const CalibrationConfig& c, const GivenValues& given,
                               const std::string& key, const std::string& word)
{
  std::vector<std::string> names;
  const auto found = given.find(key);
  if (found != given.end()) {
    names = std::get<std::vector<std::string>>(found->second);
  } else {
    for (const JointConfig& joint : c.joints) {
      const bool left = joint.name.find("left") != std::string::npos;
      const bool right = !left && joint.name.find("right") != std::string::npos;
      if (joint.kind == EncoderKind::kIncremental && (word == "left" ? left : right))
        names.push_back(joint.name);
    }
  }
  std::vector<int> indices;
  for (const std::string& name : names)
    indices.push_back(jointIndex(c, name, key));
  return indices;
}

void resolveSkidSteer(CalibrationConfig& c, const GivenValues& given)
{
  SkidSteerOptions& s = c.models.skid_steer;
  if (!uses(c, "skid_steer"))
    return;
  s.left_indices = skidSteerSide(c, given, "skid_steer.left_joints", "left");
  s.right_indices = skidSteerSide(c, given, "skid_steer.right_joints", "right");
  if (s.left_indices.empty() || s.right_indices.empty()) {
    throw std::runtime_error(
        "skid_steer: left_joints and right_joints are required (no incremental joint named "
        "*left* / *right* to default to)");
  }
  s.ticks_per_turn = c.joints[static_cast<std::size_t>(s.left_indices.front())].units_per_turn;
  for (const std::vector<int>* side : {&s.left_indices, &s.right_indices}) {
    for (int index : *side) {
      const JointConfig& joint = c.joints[static_cast<std::size_t>(index)];
      if (joint.kind != EncoderKind::kIncremental || joint.units_per_turn != s.ticks_per_turn) {
        throw std::runtime_error(
            "skid_steer: the wheel joints must be incremental with the same units_per_turn");
      }
    }
  }
  inSection("skid_steer", [&] { validate(s); });
}

/// The base odometry's joints found (wheels.source odometry), its options checked.
void resolveBaseOdometry(CalibrationConfig& c)
{
  if (!uses(c, "base_odometry"))
    return;
  if (c.wheels.source != WheelSource::kOdometry) {
    throw std::runtime_error(
        "model base_odometry takes a base's own odometry: set wheels.source "
        "to odometry and wheels.topics to its nav_msgs/Odometry topic");
  }
  BaseOdometryOptions& b = c.models.base_odometry;
  b.layout = baseOdometryLayoutForJoints(jointLayout(c));
  inSection("base_odometry", [&] { validate(b); });
}

/// The prior model (default: the fitted model when it has start values), the linear model's
/// two thresholds, the Gaussian process's options.
void resolveModelChoices(CalibrationConfig& c, const GivenValues& given)
{
  const bool has_start_values = c.model == "tricycle" || c.model == "mecanum" ||
                                c.model == "skid_steer" || c.model == "base_odometry";
  const std::string fallback =
      c.wheels.source == WheelSource::kOdometry ? "base_odometry" : "diff_drive";
  c.prior_model = givenString(given, "prior_model", has_start_values ? c.model : fallback);
  const LinearModelOptions& linear = c.models.linear;
  if (!(linear.outlier_threshold > linear.huber_threshold)) {
    throw std::runtime_error(
        "linear.outlier_threshold: " + formatConfigValue(linear.outlier_threshold) +
        " must exceed linear.huber_threshold (" + formatConfigValue(linear.huber_threshold) + ")");
  }
  inSection("gp", [&] { validate(c.models.gp); });
}

}  // namespace

CalibrationConfig parseCalibrationConfig(const std::string& text, const std::string& source)
{
  // Outside the try: its messages name the source already.
  const YAML::Node root = loadYamlDocument(text, source);
  if (root.IsNull()) {
    throw std::runtime_error(source +
                             " holds no settings (only blanks or comments): a configuration "
                             "needs at least its joints (see config/diff_drive.yaml)");
  }
  try {
    refuseDuplicateKeys(root);
    refuseUnknownKeys(root, schemaKeys());
    CalibrationConfig c;
    c.ego_motion_sources = readSources(root);
    const GivenValues given = readKeys(root, &c);
    c.joints = readJointsFor(root, c.wheels.source);
    if (c.ego_motion_sources.size() == 1) {
      // One source listed: the one-source keys say the same, for every reader of those.
      const std::vector<EgoMotionSourceConfig> listed = c.ego_motion_sources;
      c = configForSource(c, 0);
      c.ego_motion_sources = listed;
    }
    resolveModelChoices(c, given);
    validateWheelInput(c);  // before the models' joints: a model that needs wheels is named
    resolveSensor(c);
    resolveDiffDrive(c, given);
    resolveTricycle(c, given);
    resolveMecanum(c, given);
    resolveSkidSteer(c, given);
    resolveBaseOdometry(c);
    c.models.joints = jointLayout(c);
    return c;
  } catch (const std::runtime_error& error) {  // also YAML::Exception
    throw std::runtime_error(source + ": " + error.what());
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(source + ": " + error.what());
  }
}

CalibrationConfig loadCalibrationConfig(const std::string& path)
{
  return parseCalibrationConfig(readTextFile(path, "the configuration"), path);
}

std::vector<EgoMotionSourceConfig> egoMotionSources(const CalibrationConfig& config)
{
  std::vector<EgoMotionSourceConfig> sources = config.ego_motion_sources;
  if (sources.empty()) {
    EgoMotionSourceConfig one;
    one.type = config.ego_motion;
    one.topic =
        config.ego_motion == EgoMotionSource::kScan ? config.scan_topic : config.ego_motion_topic;
    one.publisher = config.ego_motion_publisher;
    sources.push_back(one);
  }
  for (EgoMotionSourceConfig& source : sources) {
    if (std::isnan(source.time_offset_s))
      source.time_offset_s = config.collector.time_offset_s;
  }
  return sources;
}

std::string egoMessageType(EgoMotionSource type)
{
  return type == EgoMotionSource::kScan    ? "LaserScan"
         : type == EgoMotionSource::kCloud ? "PointCloud2"
                                           : "pose";
}

CalibrationConfig configForSource(const CalibrationConfig& config, std::size_t index)
{
  const std::vector<EgoMotionSourceConfig> sources = egoMotionSources(config);
  if (index >= sources.size()) {
    throw std::out_of_range("ego-motion source " + std::to_string(index) +
                            ": the configuration has " + std::to_string(sources.size()));
  }
  const EgoMotionSourceConfig& source = sources[index];
  CalibrationConfig one = config;
  one.ego_motion_sources.clear();
  one.ego_motion = source.type;
  if (source.type == EgoMotionSource::kScan)
    one.scan_topic = source.topic;
  else
    one.ego_motion_topic = source.topic;
  one.ego_motion_publisher = source.publisher;
  if (!config.ego_motion_sources.empty())
    one.ego_motion_publisher_key = "ego_motion.sources[" + std::to_string(index) + "].publisher";
  one.collector.time_offset_s = source.time_offset_s;
  if (source.sensor_pose.size() == 3) {
    const Pose2 pose(source.sensor_pose[0], source.sensor_pose[1], source.sensor_pose[2]);
    one.models.diff_drive.initial_T_base_sensor = pose;
    one.models.skid_steer.initial_T_base_sensor = pose;
    one.models.mecanum.initial_T_base_sensor = pose;
    one.models.tricycle.initial.T_base_sensor = pose;
    one.models.base_odometry.initial_T_base_sensor = pose;
  }
  return one;
}

std::vector<EncoderChannelOptions> encoderChannels(const CalibrationConfig& config)
{
  std::vector<EncoderChannelOptions> channels;
  for (const JointConfig& joint : config.joints) {
    const bool incremental = joint.kind == EncoderKind::kIncremental;
    const bool wraps =
        incremental && joint.counter_bits > 0 && config.wheels.source == WheelSource::kJointState;
    channels.push_back({joint.name, joint.kind, wraps ? std::ldexp(1.0, joint.counter_bits) : 0.0,
                        incremental ? 0.0 : joint.units_per_turn,
                        joint.max_turns_per_s * joint.units_per_turn});
  }
  return channels;
}

Eigen::VectorXd applySigns(const CalibrationConfig& config, const Eigen::VectorXd& positions)
{
  Eigen::VectorXd signed_positions = positions;
  for (std::size_t j = 0; j < config.joints.size(); ++j) {
    signed_positions(static_cast<Eigen::Index>(j)) *= config.joints[j].sign;
  }
  return signed_positions;
}

JointLayout jointLayout(const CalibrationConfig& config)
{
  JointLayout layout;
  for (const JointConfig& joint : config.joints) {
    layout.names.push_back(joint.name);
    layout.kinds.push_back(joint.kind);
  }
  return layout;
}

std::shared_ptr<MotionModel> priorModel(const CalibrationConfig& config)
{
  if (config.prior_model == "none")
    return nullptr;
  return makeModel(config.prior_model, config.models);
}

std::optional<Pose2> priorSensorPose(const CalibrationConfig& config)
{
  if (config.prior_model == "diff_drive")
    return config.models.diff_drive.initial_T_base_sensor;
  if (config.prior_model == "tricycle")
    return config.models.tricycle.initial.T_base_sensor;
  if (config.prior_model == "mecanum")
    return config.models.mecanum.initial_T_base_sensor;
  if (config.prior_model == "skid_steer")
    return config.models.skid_steer.initial_T_base_sensor;
  if (config.prior_model == "base_odometry")
    return config.models.base_odometry.initial_T_base_sensor;
  return std::nullopt;
}

MotionPredictor priorPredictor(const CalibrationConfig& config)
{
  if (config.prior_model == "tricycle") {
    const TricycleModelOptions options = config.models.tricycle;
    return [options](const std::vector<EncoderSample>& samples) {
      return predictTricycleSensorMotion(options.initial, options.layout, samples);
    };
  }
  if (config.prior_model == "mecanum") {
    // The unfitted model predicts with its start values: the nominal robot.
    const std::shared_ptr<MotionModel> nominal = makeModel("mecanum", config.models);
    return [nominal](const std::vector<EncoderSample>& samples) {
      return nominal->predict(samples).mean;
    };
  }
  if (config.prior_model == "base_odometry") {
    // Unfitted: the base's own odometry at the start scales.
    const std::shared_ptr<MotionModel> nominal = makeModel("base_odometry", config.models);
    return [nominal](const std::vector<EncoderSample>& samples) {
      return nominal->predict(samples).mean;
    };
  }
  if (config.prior_model == "skid_steer") {
    // Unfitted: the geometric values (averageSides, then the diff-drive arcs).
    const auto nominal = std::make_shared<SkidSteerModel>(config.models.skid_steer);
    return [nominal](const std::vector<EncoderSample>& samples) {
      return nominal->predict(samples).mean;
    };
  }
  if (config.prior_model != "diff_drive")
    return nullptr;
  const DiffDriveOptions options = config.models.diff_drive;
  return [options](const std::vector<EncoderSample>& samples) {
    const double intrinsic[3] = {options.initial_left_radius_m, options.initial_right_radius_m,
                                 options.initial_separation_m};
    return sensorMotionFromBodyMotion(options.initial_T_base_sensor,
                                      integrateDiffDriveMotion(intrinsic, options.layout, samples));
  };
}

}  // namespace odometry_calibration
