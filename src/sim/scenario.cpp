#include "odometry_calibration/sim/scenario.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/common/yaml_reading.h"

namespace odometry_calibration {
namespace sim {
namespace {

Pose2 readPose(const YAML::Node& node, const std::string& where, const Pose2& fallback)
{
  if (!node)
    return fallback;
  checkYamlKeys(node, {"x", "y", "theta"}, where);
  double x = fallback.x(), y = fallback.y(), theta = fallback.theta();
  readYaml(node, "x", &x);
  readYaml(node, "y", &y);
  readYaml(node, "theta", &theta);
  return Pose2(x, y, theta);
}

std::string directoryOf(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

/// The laser's rays, rate, ranges and noise model.
void validateLaserNoise(const LaserOptions& laser)
{
  require(laser.rays >= 2, "laser.rays must be >= 2");
  require(laser.fov_rad > 0.0 && laser.fov_rad <= 2.0 * M_PI, "laser.fov_rad must be in (0, 2 pi]");
  require(laser.rate_hz > 0.0, "laser.rate_hz must be > 0");
  require(laser.range_noise_m >= 0.0, "laser.range_noise_m must be >= 0");
  require(laser.min_range_m >= 0.0 && laser.max_range_m > laser.min_range_m,
          "laser ranges: need 0 <= min_range_m < max_range_m");
  require(laser.dropout_probability >= 0.0 && laser.dropout_probability < 1.0,
          "laser.dropout_probability must be in [0, 1)");
  require(laser.range_noise_per_m >= 0.0 && laser.range_resolution_m >= 0.0 &&
              laser.beam_divergence_rad >= 0.0,
          "laser.range_noise_per_m, range_resolution_m and beam_divergence_rad must be >= 0");
  require(std::isfinite(laser.range_noise_correlation) && laser.range_noise_correlation >= 0.0 &&
              laser.range_noise_correlation <= 0.95,
          "laser.range_noise_correlation must be in [0, 0.95]");
  require(laser.mixed_pixel_probability >= 0.0 && laser.mixed_pixel_probability <= 1.0,
          "laser.mixed_pixel_probability must be in [0, 1]");
  require(laser.dark_dropout_probability >= 0.0 && laser.dark_dropout_probability <= 1.0,
          "laser.dark_dropout_probability must be in [0, 1]");
  require(std::isfinite(laser.range_ripple_m) && laser.range_ripple_m >= 0.0,
          "laser.range_ripple_m must be >= 0 metres");
  require(std::isfinite(laser.range_ripple_period_rays) && laser.range_ripple_period_rays >= 2.0,
          "laser.range_ripple_period_rays must be at least 2 rays");
}

/// The laser's names, type and the multibeam geometry.
void validateLaserGeometry(const LaserOptions& laser)
{
  require(!laser.frame_id.empty() && !laser.topic.empty(), "laser frame_id/topic are empty");
  require(laser.type == "planar" || laser.type == "multibeam",
          "laser.type must be planar or multibeam");
  require(laser.rings >= 1 && laser.rings <= 256, "laser.rings must be in [1, 256]");
  require(laser.elevation_min_rad <= laser.elevation_max_rad &&
              std::abs(laser.elevation_min_rad) < 1.5 && std::abs(laser.elevation_max_rad) < 1.5,
          "laser elevations: need min <= max within (-1.5, 1.5) rad");
  require(laser.horizontal_step_rad >= 1e-4 && laser.horizontal_step_rad <= 0.1,
          "laser.horizontal_step_rad must be in [1e-4, 0.1] rad");
  require(laser.height_m > 0.0 && std::isfinite(laser.height_m), "laser.height_m must be > 0");
  require(std::abs(laser.roll_rad) < 0.5 && std::abs(laser.pitch_rad) < 0.5,
          "laser roll_rad and pitch_rad must be within 0.5 rad");
  require(laser.point_times == "relative" || laser.point_times == "absolute",
          "laser.point_times must be relative or absolute");
  require(std::isfinite(laser.time_offset_s) && std::abs(laser.time_offset_s) < 10.0,
          "laser.time_offset_s must be within 10 s");
}

/// The extra lasers: planar, each on a topic and frame of its own.
void validateExtraLasers(const Scenario& s)
{
  std::set<std::string> topics{s.laser.topic}, frames{s.laser.frame_id};
  for (std::size_t k = 0; k < s.extra_lasers.size(); ++k) {
    const LaserOptions& laser = s.extra_lasers[k];
    const std::string which = "lasers[" + std::to_string(k + 1) + "]";
    try {
      validateLaserNoise(laser);
      validateLaserGeometry(laser);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(which + ": " + error.what());
    }
    require(laser.type == "planar", which + ": only the first laser may be multibeam");
    require(topics.insert(laser.topic).second,
            which + ": topic '" + laser.topic + "' is another laser's too");
    require(frames.insert(laser.frame_id).second,
            which + ": frame_id '" + laser.frame_id + "' is another laser's too");
  }
}

/// The changes: in time order, mounting moves within reach, encoder stamps never going back.
void validateChanges(const Scenario& s)
{
  double previous_change_s = 0.0, offset_s = s.encoders.time_offset_s;
  for (const ParameterChange& change : s.changes) {
    require(change.at_s >= previous_change_s && std::isfinite(change.at_s),
            "changes must be in time order at times >= 0 s");
    require(change.laser_index <= s.extra_lasers.size(),
            "changes: laser " + std::to_string(change.laser_index) + " does not exist (" +
                std::to_string(s.extra_lasers.size() + 1) + " lasers, counted from 0)");
    require(std::abs(change.laser_yaw_change_rad) < M_PI,
            "changes: laser_yaw_change_rad must be within pi");
    require(std::abs(change.laser_x_change_m) < 10.0 && std::abs(change.laser_y_change_m) < 10.0,
            "changes: laser_x_change_m and laser_y_change_m must be within 10 m");
    offset_s += change.time_offset_change_s;
    require(std::abs(offset_s) < 10.0,
            "changes: encoders.time_offset_s plus the time_offset_change_s so far must stay "
            "within 10 s");
    require(change.time_offset_change_s > -1.0 / s.encoders.rate_hz,
            "changes: a negative time_offset_change_s must be shorter than one encoder period "
            "(the encoder stamps would go backwards)");
    previous_change_s = change.at_s;
  }
}

}  // namespace

void validate(const Scenario& s)
{
  require(s.duration_s > 0.0 && std::isfinite(s.duration_s), "duration_s must be > 0");
  require(s.start_time_s >= 1.0 && s.start_time_s < 4e9, "start_time_s must be in [1, 4e9) s");
  validateLaserNoise(s.laser);
  validateLaserGeometry(s.laser);
  validateExtraLasers(s);
  require(s.encoders.rate_hz > 0.0, "encoders.rate_hz must be > 0");
  require(s.encoders.rate_jitter_s >= 0.0 && s.encoders.rate_jitter_s < 0.5 / s.encoders.rate_hz,
          "encoders.rate_jitter_s must be in [0, half the period 1 / rate_hz)");
  require(s.encoders.counter_bits >= 0 && s.encoders.counter_bits <= 52,
          "encoders.counter_bits must be in [0, 52]");
  require(std::abs(s.encoders.time_offset_s) < 10.0, "encoders.time_offset_s must be within 10 s");
  require(s.encoders.initial_ticks >= 0.0, "encoders.initial_ticks must be >= 0");
  require(s.encoders.output == "joint_state" || s.encoders.output == "ticks" ||
              s.encoders.output == "joint_velocity" || s.encoders.output == "odometry",
          "encoders.output must be joint_state, ticks, joint_velocity or odometry");
  require(std::abs(s.encoders.odometry_translation_error) < 0.5 &&
              std::abs(s.encoders.odometry_rotation_error) < 0.5,
          "encoders.odometry_translation_error and odometry_rotation_error must be within 0.5");
  require(s.encoders.tick_stagger_s >= 0.0 && s.encoders.tick_stagger_s < 0.5 / s.encoders.rate_hz,
          "encoders.tick_stagger_s must be in [0, half the period 1 / rate_hz)");
  require(s.tracker.translation_noise_m >= 0.0 && s.tracker.rotation_noise_rad >= 0.0,
          "tracker noise must be >= 0");
  validate(s.imu);
  validate(s.motion);
  validateChanges(s);
}

namespace {

/// The scenario's top-level keys: name, seed, times, topics, the world's file (a name in
/// worlds_directory, or a .yaml path relative to the scenario's folder) and the start pose.
void readScenarioTop(const YAML::Node& root, const std::string& path,
                     const std::string& worlds_directory, Scenario& s)
{
  checkYamlKeys(root,
                {"name", "seed", "duration_s", "start_time_s", "world", "start_pose", "robot",
                 "laser", "lasers", "encoders", "motion", "tracker", "imu", "changes",
                 "ground_truth_topic", "ground_truth_frame"},
                path);
  readYaml(root, "name", &s.name);
  readYaml(root, "seed", &s.seed);
  readYaml(root, "duration_s", &s.duration_s);
  readYaml(root, "start_time_s", &s.start_time_s);
  readYaml(root, "ground_truth_topic", &s.ground_truth_topic);
  readYaml(root, "ground_truth_frame", &s.ground_truth_frame);
  std::string world = "office";
  readYaml(root, "world", &world);
  if (world.size() > 5 && world.substr(world.size() - 5) == ".yaml") {
    s.world_path = world[0] == '/' ? world : directoryOf(path) + "/" + world;
  } else {
    s.world_path = worlds_directory + "/" + world + ".yaml";
  }
  s.start_pose = readPose(root["start_pose"], path + ": start_pose", Pose2());
}

/// robot: its type and its parameters (checked by makeRobot).
void readRobotYaml(const YAML::Node& robot, RobotOptions& options)
{
  if (!robot)
    return;
  if (!robot.IsMap())
    throw std::runtime_error("expected a map");
  for (const auto& entry : robot) {
    const std::string key = entry.first.as<std::string>();
    if (key == "type") {
      options.type = entry.second.as<std::string>();
    } else {
      options.parameters[key] = entry.second.as<double>();
    }
  }
}

/// laser: the names, the type and a multibeam lidar's geometry.
void readLaserTypeYaml(const YAML::Node& laser, LaserOptions& options)
{
  readYaml(laser, "frame_id", &options.frame_id);
  readYaml(laser, "topic", &options.topic);
  readYaml(laser, "type", &options.type);
  readYaml(laser, "rings", &options.rings);
  readYaml(laser, "elevation_min_rad", &options.elevation_min_rad);
  readYaml(laser, "elevation_max_rad", &options.elevation_max_rad);
  readYaml(laser, "horizontal_step_rad", &options.horizontal_step_rad);
  readYaml(laser, "height_m", &options.height_m);
  readYaml(laser, "roll_rad", &options.roll_rad);
  readYaml(laser, "pitch_rad", &options.pitch_rad);
  readYaml(laser, "point_times", &options.point_times);
}

/// laser: the pose on the base and the sensor model.
void readLaserYaml(const YAML::Node& laser, const std::string& where, LaserOptions& options)
{
  checkYamlKeys(laser,
                {"pose",
                 "rays",
                 "fov_rad",
                 "rate_hz",
                 "range_noise_m",
                 "min_range_m",
                 "max_range_m",
                 "dropout_probability",
                 "sweep",
                 "range_noise_per_m",
                 "range_noise_correlation",
                 "range_resolution_m",
                 "mixed_pixel_probability",
                 "beam_divergence_rad",
                 "dark_dropout_probability",
                 "range_ripple_m",
                 "range_ripple_period_rays",
                 "frame_id",
                 "topic",
                 "type",
                 "rings",
                 "elevation_min_rad",
                 "elevation_max_rad",
                 "horizontal_step_rad",
                 "height_m",
                 "roll_rad",
                 "pitch_rad",
                 "point_times",
                 "time_offset_s"},
                where);
  if (laser) {
    options.T_base_laser = readPose(laser["pose"], where + ".pose", options.T_base_laser);
  }
  readYaml(laser, "rays", &options.rays);
  readYaml(laser, "fov_rad", &options.fov_rad);
  readYaml(laser, "rate_hz", &options.rate_hz);
  readYaml(laser, "range_noise_m", &options.range_noise_m);
  readYaml(laser, "min_range_m", &options.min_range_m);
  readYaml(laser, "max_range_m", &options.max_range_m);
  readYaml(laser, "dropout_probability", &options.dropout_probability);
  readYaml(laser, "sweep", &options.sweep);
  readYaml(laser, "range_noise_per_m", &options.range_noise_per_m);
  readYaml(laser, "range_noise_correlation", &options.range_noise_correlation);
  readYaml(laser, "range_resolution_m", &options.range_resolution_m);
  readYaml(laser, "mixed_pixel_probability", &options.mixed_pixel_probability);
  readYaml(laser, "beam_divergence_rad", &options.beam_divergence_rad);
  readYaml(laser, "dark_dropout_probability", &options.dark_dropout_probability);
  readYaml(laser, "range_ripple_m", &options.range_ripple_m);
  readYaml(laser, "range_ripple_period_rays", &options.range_ripple_period_rays);
  readYaml(laser, "time_offset_s", &options.time_offset_s);
  readLaserTypeYaml(laser, options);
}

/// lasers: the robot's lasers, the first into s.laser, the others into
/// s.extra_lasers; each entry has the keys of `laser:`. Not together with `laser:`.
void readLasersYaml(const YAML::Node& root, const std::string& path, std::string& where,
                    Scenario& s)
{
  const YAML::Node lasers = root["lasers"];
  if (!lasers)
    return;
  if (root["laser"])
    throw std::runtime_error("give either laser: (one laser) or lasers: (a list), not both");
  if (!lasers.IsSequence() || lasers.size() == 0)
    throw std::runtime_error("lasers: expected a list of at least one laser");
  for (std::size_t k = 0; k < lasers.size(); ++k) {
    where = path + ": lasers[" + std::to_string(k) + "]";
    LaserOptions options;
    readLaserYaml(lasers[k], where, options);
    if (k == 0)
      s.laser = options;
    else
      s.extra_lasers.push_back(options);
  }
}

/// encoders: rate, topic, joints, units, counter width, start and time offset.
void readEncodersYaml(const YAML::Node& encoders, const std::string& where, EncoderOptions& options)
{
  checkYamlKeys(
      encoders,
      {"rate_hz", "rate_jitter_s", "topic", "joint_names", "units", "counter_bits", "initial_ticks",
       "time_offset_s", "output", "tick_topics", "tick_type", "tick_stagger_s", "odometry_topic",
       "odometry_translation_error", "odometry_rotation_error"},
      where);
  readYaml(encoders, "rate_hz", &options.rate_hz);
  readYaml(encoders, "rate_jitter_s", &options.rate_jitter_s);
  readYaml(encoders, "topic", &options.topic);
  readYaml(encoders, "joint_names", &options.joint_names);
  std::string units = "ticks";
  readYaml(encoders, "units", &units);
  if (units != "ticks" && units != "radians") {
    throw std::runtime_error("units must be 'ticks' or 'radians', got '" + units + "'");
  }
  options.output_ticks = units == "ticks";
  readYaml(encoders, "counter_bits", &options.counter_bits);
  readYaml(encoders, "initial_ticks", &options.initial_ticks);
  readYaml(encoders, "time_offset_s", &options.time_offset_s);
  readYaml(encoders, "output", &options.output);
  readYaml(encoders, "tick_topics", &options.tick_topics);
  readYaml(encoders, "tick_type", &options.tick_type);
  readYaml(encoders, "tick_stagger_s", &options.tick_stagger_s);
  readYaml(encoders, "odometry_topic", &options.odometry_topic);
  readYaml(encoders, "odometry_translation_error", &options.odometry_translation_error);
  readYaml(encoders, "odometry_rotation_error", &options.odometry_rotation_error);
}

/// tracker: whether a pose tracker publishes, its noise, topic and frame.
void readTrackerYaml(const YAML::Node& tracker, const std::string& where, TrackerOptions& options)
{
  checkYamlKeys(tracker,
                {"enabled", "translation_noise_m", "rotation_noise_rad", "topic", "frame_id"},
                where);
  readYaml(tracker, "enabled", &options.enabled);
  readYaml(tracker, "translation_noise_m", &options.translation_noise_m);
  readYaml(tracker, "rotation_noise_rad", &options.rotation_noise_rad);
  readYaml(tracker, "topic", &options.topic);
  readYaml(tracker, "frame_id", &options.frame_id);
}

/// imu: whether the IMU publishes, its gyro's errors, clock, mounting, topic and frame.
void readImuYaml(const YAML::Node& imu, const std::string& where, ImuOptions& options)
{
  checkYamlKeys(imu,
                {"enabled", "rate_hz", "scale", "bias_rad_s", "bias_random_walk", "noise_rad_s",
                 "time_offset_s", "roll_rad", "pitch_rad", "topic", "frame_id"},
                where);
  readYaml(imu, "enabled", &options.enabled);
  readYaml(imu, "rate_hz", &options.rate_hz);
  readYaml(imu, "scale", &options.scale);
  readYaml(imu, "bias_rad_s", &options.bias_rad_s);
  readYaml(imu, "bias_random_walk", &options.bias_random_walk);
  readYaml(imu, "noise_rad_s", &options.noise_rad_s);
  readYaml(imu, "time_offset_s", &options.time_offset_s);
  readYaml(imu, "roll_rad", &options.roll_rad);
  readYaml(imu, "pitch_rad", &options.pitch_rad);
  readYaml(imu, "topic", &options.topic);
  readYaml(imu, "frame_id", &options.frame_id);
}

/// motion: the drive plan, and its script's steps (`where` names the step being read).
void readMotionYaml(const YAML::Node& motion, const std::string& path, std::string& where,
                    DrivePlanOptions& options)
{
  checkYamlKeys(
      motion,
      {"type", "max_speed_mps", "max_turn_rate_radps", "min_segment_s", "max_segment_s",
       "clearance_m", "lookahead_s", "max_acceleration_mps2", "max_angular_acceleration_radps2",
       "script", "left_turns", "right_turns", "turning_in_place"},
      where);
  readYaml(motion, "type", &options.type);
  readYaml(motion, "max_speed_mps", &options.max_speed_mps);
  readYaml(motion, "max_turn_rate_radps", &options.max_turn_rate_radps);
  readYaml(motion, "min_segment_s", &options.min_segment_s);
  readYaml(motion, "max_segment_s", &options.max_segment_s);
  readYaml(motion, "clearance_m", &options.clearance_m);
  readYaml(motion, "lookahead_s", &options.lookahead_s);
  readYaml(motion, "max_acceleration_mps2", &options.max_acceleration_mps2);
  readYaml(motion, "max_angular_acceleration_radps2", &options.max_angular_acceleration_radps2);
  readYaml(motion, "left_turns", &options.left_turns);
  readYaml(motion, "right_turns", &options.right_turns);
  readYaml(motion, "turning_in_place", &options.turning_in_place);
  if (!motion || !motion["script"])
    return;
  std::size_t index = 0;
  for (const YAML::Node& step : motion["script"]) {
    where = path + ": motion.script[" + std::to_string(index++) + "]";
    checkYamlKeys(step, {"duration_s", "vx_mps", "vy_mps", "omega_radps"}, where);
    ScriptedMotion scripted;
    readYaml(step, "duration_s", &scripted.duration_s);
    readYaml(step, "vx_mps", &scripted.twist.vx_mps);
    readYaml(step, "vy_mps", &scripted.twist.vy_mps);
    readYaml(step, "omega_radps", &scripted.twist.omega_radps);
    options.script.push_back(scripted);
  }
}

/// A change's `laser:`: an index into the scenario's lasers, or a laser's frame_id or topic.
std::size_t changedLaserIndex(const YAML::Node& laser, const Scenario& s)
{
  const std::vector<LaserOptions> lasers = allLasers(s);
  const std::string text = laser.as<std::string>();
  for (std::size_t k = 0; k < lasers.size(); ++k) {
    if (text == lasers[k].frame_id || text == lasers[k].topic || text == std::to_string(k))
      return k;
  }
  throw std::runtime_error("laser: '" + text + "' is no laser's index (from 0), frame_id or topic");
}

/// changes: the robot's and the laser's changes mid-run (`where` names the entry being read),
/// each checked to make a valid robot (unknown keys named now, not mid-run).
void readChangesYaml(const YAML::Node& changes, const std::string& path, std::string& where,
                     Scenario& s)
{
  if (!changes)
    return;
  std::size_t index = 0;
  for (const YAML::Node& entry : changes) {
    where = path + ": changes[" + std::to_string(index++) + "]";
    checkYamlKeys(entry,
                  {"at_s", "robot", "laser", "laser_x_change_m", "laser_y_change_m",
                   "laser_yaw_change_rad", "time_offset_change_s"},
                  where);
    ParameterChange change;
    readYaml(entry, "at_s", &change.at_s);
    if (const YAML::Node laser = entry["laser"])
      change.laser_index = changedLaserIndex(laser, s);
    readYaml(entry, "laser_x_change_m", &change.laser_x_change_m);
    readYaml(entry, "laser_y_change_m", &change.laser_y_change_m);
    readYaml(entry, "laser_yaw_change_rad", &change.laser_yaw_change_rad);
    readYaml(entry, "time_offset_change_s", &change.time_offset_change_s);
    if (const YAML::Node robot_change = entry["robot"]) {
      if (!robot_change.IsMap())
        throw std::runtime_error("robot: expected a map of robot keys to new values");
      for (const auto& parameter : robot_change)
        change.robot_parameters[parameter.first.as<std::string>()] = parameter.second.as<double>();
    }
    s.changes.push_back(change);
  }
  RobotOptions changed = s.robot;
  for (const ParameterChange& change : s.changes) {
    for (const auto& [key, value] : change.robot_parameters)
      changed.parameters[key] = value;
    makeRobot(changed);
  }
}

}  // namespace

Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory)
{
  Scenario s;
  std::string where = path;
  try {
    const YAML::Node root = loadYamlDocument(readTextFile(path, "the scenario"), path);
    readScenarioTop(root, path, worlds_directory, s);
    where = path + ": robot";
    readRobotYaml(root["robot"], s.robot);
    where = path + ": laser";
    readLaserYaml(root["laser"], where, s.laser);
    readLasersYaml(root, path, where, s);
    where = path + ": encoders";
    readEncodersYaml(root["encoders"], where, s.encoders);
    where = path + ": tracker";
    readTrackerYaml(root["tracker"], where, s.tracker);
    where = path + ": imu";
    readImuYaml(root["imu"], where, s.imu);
    where = path + ": motion";
    readMotionYaml(root["motion"], path, where, s.motion);
    readChangesYaml(root["changes"], path, where, s);
    where = path;
    validate(s);
  } catch (...) {
    rethrowWithYamlContext(path, where);
  }
  return s;
}

Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory,
                          const ScenarioOverrides& overrides)
{
  Scenario scenario = loadScenarioYaml(path, worlds_directory);
  if (overrides.seed >= 0.0)
    scenario.seed = static_cast<unsigned>(overrides.seed);
  if (overrides.duration_s > 0.0)
    scenario.duration_s = overrides.duration_s;
  EncoderOptions& encoders = scenario.encoders;
  if (!overrides.wheel_output.empty())
    encoders.output = overrides.wheel_output;
  if (overrides.counter_bits >= 0)
    encoders.counter_bits = overrides.counter_bits;
  if (!overrides.tick_type.empty())
    encoders.tick_type = overrides.tick_type;
  if (overrides.tick_stagger_s >= 0.0)
    encoders.tick_stagger_s = overrides.tick_stagger_s;
  if (std::isfinite(overrides.odometry_translation_error))
    encoders.odometry_translation_error = overrides.odometry_translation_error;
  if (std::isfinite(overrides.odometry_rotation_error))
    encoders.odometry_rotation_error = overrides.odometry_rotation_error;
  validate(scenario);
  return scenario;
}

std::vector<LaserOptions> allLasers(const Scenario& scenario)
{
  std::vector<LaserOptions> lasers{scenario.laser};
  lasers.insert(lasers.end(), scenario.extra_lasers.begin(), scenario.extra_lasers.end());
  return lasers;
}

std::string shippedWorldsDirectory()
{
  return std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds";
}
}  // namespace sim
}  // namespace odometry_calibration
