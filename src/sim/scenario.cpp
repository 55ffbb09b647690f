#include "odometry_calibration/sim/scenario.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

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

}  // namespace

void validate(const Scenario& s)
{
  auto require = [](bool ok, const std::string& message) {
    if (!ok)
      throw std::invalid_argument(message);
  };
  require(s.duration_s > 0.0 && std::isfinite(s.duration_s), "duration_s must be > 0");
  require(s.start_time_s >= 1.0 && s.start_time_s < 4e9, "start_time_s must be in [1, 4e9) s");
  require(s.laser.rays >= 2, "laser.rays must be >= 2");
  require(s.laser.fov_rad > 0.0 && s.laser.fov_rad <= 2.0 * M_PI,
          "laser.fov_rad must be in (0, 2 pi]");
  require(s.laser.rate_hz > 0.0, "laser.rate_hz must be > 0");
  require(s.laser.range_noise_m >= 0.0, "laser.range_noise_m must be >= 0");
  require(s.laser.min_range_m >= 0.0 && s.laser.max_range_m > s.laser.min_range_m,
          "laser ranges: need 0 <= min_range_m < max_range_m");
  require(s.laser.dropout_probability >= 0.0 && s.laser.dropout_probability < 1.0,
          "laser.dropout_probability must be in [0, 1)");
  require(s.laser.range_noise_per_m >= 0.0 && s.laser.range_resolution_m >= 0.0 &&
              s.laser.beam_divergence_rad >= 0.0,
          "laser.range_noise_per_m, range_resolution_m and beam_divergence_rad must be >= 0");
  require(std::isfinite(s.laser.range_noise_correlation) &&
              s.laser.range_noise_correlation >= 0.0 && s.laser.range_noise_correlation <= 0.95,
          "laser.range_noise_correlation must be in [0, 0.95]");
  require(s.laser.mixed_pixel_probability >= 0.0 && s.laser.mixed_pixel_probability <= 1.0,
          "laser.mixed_pixel_probability must be in [0, 1]");
  require(s.laser.dark_dropout_probability >= 0.0 && s.laser.dark_dropout_probability <= 1.0,
          "laser.dark_dropout_probability must be in [0, 1]");
  require(std::isfinite(s.laser.range_ripple_m) && s.laser.range_ripple_m >= 0.0,
          "laser.range_ripple_m must be >= 0 metres");
  require(
      std::isfinite(s.laser.range_ripple_period_rays) && s.laser.range_ripple_period_rays >= 2.0,
      "laser.range_ripple_period_rays must be at least 2 rays");
  require(!s.laser.frame_id.empty() && !s.laser.topic.empty(), "laser frame_id/topic are empty");
  require(s.laser.type == "planar" || s.laser.type == "multibeam",
          "laser.type must be planar or multibeam");
  require(s.laser.rings >= 1 && s.laser.rings <= 256, "laser.rings must be in [1, 256]");
  require(s.laser.elevation_min_rad <= s.laser.elevation_max_rad &&
              std::abs(s.laser.elevation_min_rad) < 1.5 &&
              std::abs(s.laser.elevation_max_rad) < 1.5,
          "laser elevations: need min <= max within (-1.5, 1.5) rad");
  require(s.laser.horizontal_step_rad >= 1e-4 && s.laser.horizontal_step_rad <= 0.1,
          "laser.horizontal_step_rad must be in [1e-4, 0.1] rad");
  require(s.laser.height_m > 0.0 && std::isfinite(s.laser.height_m), "laser.height_m must be > 0");
  require(std::abs(s.laser.roll_rad) < 0.5 && std::abs(s.laser.pitch_rad) < 0.5,
          "laser roll_rad and pitch_rad must be within 0.5 rad");
  require(s.laser.point_times == "relative" || s.laser.point_times == "absolute",
          "laser.point_times must be relative or absolute");
  require(s.encoders.rate_hz > 0.0, "encoders.rate_hz must be > 0");
  require(s.encoders.counter_bits >= 0 && s.encoders.counter_bits <= 52,
          "encoders.counter_bits must be in [0, 52]");
  require(std::abs(s.encoders.time_offset_s) < 10.0, "encoders.time_offset_s must be within 10 s");
  require(s.encoders.initial_ticks >= 0.0, "encoders.initial_ticks must be >= 0");
  require(s.tracker.translation_noise_m >= 0.0 && s.tracker.rotation_noise_rad >= 0.0,
          "tracker noise must be >= 0");
  validate(s.motion);
  double previous_change_s = 0.0;
  for (const ParameterChange& change : s.changes) {
    require(change.at_s >= previous_change_s && std::isfinite(change.at_s),
            "changes must be in time order at times >= 0 s");
    require(std::abs(change.laser_yaw_change_rad) < M_PI,
            "changes: laser_yaw_change_rad must be within pi");
    previous_change_s = change.at_s;
  }
}

Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory)
{
  Scenario s;
  std::string where = path;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    checkYamlKeys(
        root,
        {"name", "seed", "duration_s", "start_time_s", "world", "start_pose", "robot", "laser",
         "encoders", "motion", "tracker", "changes", "ground_truth_topic", "ground_truth_frame"},
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

    where = path + ": robot";
    const YAML::Node robot = root["robot"];
    if (robot) {
      if (!robot.IsMap())
        throw std::runtime_error("expected a map");
      for (const auto& entry : robot) {
        const std::string key = entry.first.as<std::string>();
        if (key == "type") {
          s.robot.type = entry.second.as<std::string>();
        } else {
          s.robot.parameters[key] = entry.second.as<double>();
        }
      }
    }

    where = path + ": laser";
    const YAML::Node laser = root["laser"];
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
                   "point_times"},
                  where);
    if (laser) {
      s.laser.T_base_laser = readPose(laser["pose"], where + ".pose", s.laser.T_base_laser);
    }
    readYaml(laser, "rays", &s.laser.rays);
    readYaml(laser, "fov_rad", &s.laser.fov_rad);
    readYaml(laser, "rate_hz", &s.laser.rate_hz);
    readYaml(laser, "range_noise_m", &s.laser.range_noise_m);
    readYaml(laser, "min_range_m", &s.laser.min_range_m);
    readYaml(laser, "max_range_m", &s.laser.max_range_m);
    readYaml(laser, "dropout_probability", &s.laser.dropout_probability);
    readYaml(laser, "sweep", &s.laser.sweep);
    readYaml(laser, "range_noise_per_m", &s.laser.range_noise_per_m);
    readYaml(laser, "range_noise_correlation", &s.laser.range_noise_correlation);
    readYaml(laser, "range_resolution_m", &s.laser.range_resolution_m);
    readYaml(laser, "mixed_pixel_probability", &s.laser.mixed_pixel_probability);
    readYaml(laser, "beam_divergence_rad", &s.laser.beam_divergence_rad);
    readYaml(laser, "dark_dropout_probability", &s.laser.dark_dropout_probability);
    readYaml(laser, "range_ripple_m", &s.laser.range_ripple_m);
    readYaml(laser, "range_ripple_period_rays", &s.laser.range_ripple_period_rays);
    readYaml(laser, "frame_id", &s.laser.frame_id);
    readYaml(laser, "topic", &s.laser.topic);
    readYaml(laser, "type", &s.laser.type);
    readYaml(laser, "rings", &s.laser.rings);
    readYaml(laser, "elevation_min_rad", &s.laser.elevation_min_rad);
    readYaml(laser, "elevation_max_rad", &s.laser.elevation_max_rad);
    readYaml(laser, "horizontal_step_rad", &s.laser.horizontal_step_rad);
    readYaml(laser, "height_m", &s.laser.height_m);
    readYaml(laser, "roll_rad", &s.laser.roll_rad);
    readYaml(laser, "pitch_rad", &s.laser.pitch_rad);
    readYaml(laser, "point_times", &s.laser.point_times);

    where = path + ": encoders";
    const YAML::Node encoders = root["encoders"];
    checkYamlKeys(encoders,
                  {"rate_hz", "topic", "joint_names", "units", "counter_bits", "initial_ticks",
                   "time_offset_s"},
                  where);
    readYaml(encoders, "rate_hz", &s.encoders.rate_hz);
    readYaml(encoders, "topic", &s.encoders.topic);
    readYaml(encoders, "joint_names", &s.encoders.joint_names);
    std::string units = "ticks";
    readYaml(encoders, "units", &units);
    if (units != "ticks" && units != "radians") {
      throw std::runtime_error("units must be 'ticks' or 'radians', got '" + units + "'");
    }
    s.encoders.output_ticks = units == "ticks";
    readYaml(encoders, "counter_bits", &s.encoders.counter_bits);
    readYaml(encoders, "initial_ticks", &s.encoders.initial_ticks);
    readYaml(encoders, "time_offset_s", &s.encoders.time_offset_s);

    where = path + ": tracker";
    const YAML::Node tracker = root["tracker"];
    checkYamlKeys(tracker,
                  {"enabled", "translation_noise_m", "rotation_noise_rad", "topic", "frame_id"},
                  where);
    readYaml(tracker, "enabled", &s.tracker.enabled);
    readYaml(tracker, "translation_noise_m", &s.tracker.translation_noise_m);
    readYaml(tracker, "rotation_noise_rad", &s.tracker.rotation_noise_rad);
    readYaml(tracker, "topic", &s.tracker.topic);
    readYaml(tracker, "frame_id", &s.tracker.frame_id);

    where = path + ": motion";
    const YAML::Node motion = root["motion"];
    checkYamlKeys(
        motion,
        {"type", "max_speed_mps", "max_turn_rate_radps", "min_segment_s", "max_segment_s",
         "clearance_m", "lookahead_s", "max_acceleration_mps2", "max_angular_acceleration_radps2",
         "script", "left_turns", "right_turns", "turning_in_place"},
        where);
    readYaml(motion, "type", &s.motion.type);
    readYaml(motion, "max_speed_mps", &s.motion.max_speed_mps);
    readYaml(motion, "max_turn_rate_radps", &s.motion.max_turn_rate_radps);
    readYaml(motion, "min_segment_s", &s.motion.min_segment_s);
    readYaml(motion, "max_segment_s", &s.motion.max_segment_s);
    readYaml(motion, "clearance_m", &s.motion.clearance_m);
    readYaml(motion, "lookahead_s", &s.motion.lookahead_s);
    readYaml(motion, "max_acceleration_mps2", &s.motion.max_acceleration_mps2);
    readYaml(motion, "max_angular_acceleration_radps2", &s.motion.max_angular_acceleration_radps2);
    readYaml(motion, "left_turns", &s.motion.left_turns);
    readYaml(motion, "right_turns", &s.motion.right_turns);
    readYaml(motion, "turning_in_place", &s.motion.turning_in_place);
    if (motion && motion["script"]) {
      std::size_t index = 0;
      for (const YAML::Node& step : motion["script"]) {
        where = path + ": motion.script[" + std::to_string(index++) + "]";
        checkYamlKeys(step, {"duration_s", "vx_mps", "vy_mps", "omega_radps"}, where);
        ScriptedMotion scripted;
        readYaml(step, "duration_s", &scripted.duration_s);
        readYaml(step, "vx_mps", &scripted.twist.vx_mps);
        readYaml(step, "vy_mps", &scripted.twist.vy_mps);
        readYaml(step, "omega_radps", &scripted.twist.omega_radps);
        s.motion.script.push_back(scripted);
      }
    }
    if (const YAML::Node changes = root["changes"]) {
      std::size_t index = 0;
      for (const YAML::Node& entry : changes) {
        where = path + ": changes[" + std::to_string(index++) + "]";
        checkYamlKeys(entry, {"at_s", "robot", "laser_yaw_change_rad"}, where);
        ParameterChange change;
        readYaml(entry, "at_s", &change.at_s);
        readYaml(entry, "laser_yaw_change_rad", &change.laser_yaw_change_rad);
        if (const YAML::Node robot_change = entry["robot"]) {
          if (!robot_change.IsMap())
            throw std::runtime_error("robot: expected a map of robot keys to new values");
          for (const auto& parameter : robot_change)
            change.robot_parameters[parameter.first.as<std::string>()] =
                parameter.second.as<double>();
        }
        s.changes.push_back(change);
      }
      // Every change must make a valid robot (unknown keys named now, not mid-run).
      RobotOptions changed = s.robot;
      for (const ParameterChange& change : s.changes) {
        for (const auto& [key, value] : change.robot_parameters)
          changed.parameters[key] = value;
        makeRobot(changed);
      }
    }
    where = path;
    validate(s);
  } catch (...) {
    rethrowWithYamlContext(path, where);
  }
  return s;
}

std::string scenarioTruthYaml(const Scenario& s, const Robot& robot)
{
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << s.name;
  out << YAML::Key << "seed" << YAML::Value << s.seed;
  out << YAML::Key << "duration_s" << YAML::Value << s.duration_s;
  out << YAML::Key << "start_time_s" << YAML::Value << s.start_time_s;
  out << YAML::Key << "world" << YAML::Value << s.world_path;
  out << YAML::Key << "robot" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "type" << YAML::Value << s.robot.type;
  for (const auto& [key, value] : robot.trueParameters()) {
    out << YAML::Key << key << YAML::Value << value;
  }
  out << YAML::EndMap;
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  const auto specs = robot.joints();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value
        << (s.encoders.joint_names.empty() ? specs[i].name : s.encoders.joint_names[i]);
    out << YAML::Key << "kind" << YAML::Value
        << (specs[i].kind == EncoderKind::kIncremental ? "incremental" : "absolute");
    out << YAML::Key << "ticks_per_rev" << YAML::Value << specs[i].ticks_per_rev;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  const Pose2& T = s.laser.T_base_laser;
  out << YAML::Key << "T_base_laser" << YAML::Value << YAML::BeginMap << YAML::Key << "x"
      << YAML::Value << T.x() << YAML::Key << "y" << YAML::Value << T.y() << YAML::Key << "theta"
      << YAML::Value << T.theta() << YAML::EndMap;
  out << YAML::Key << "laser" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rays" << YAML::Value << s.laser.rays;
  out << YAML::Key << "fov_rad" << YAML::Value << s.laser.fov_rad;
  out << YAML::Key << "rate_hz" << YAML::Value << s.laser.rate_hz;
  out << YAML::Key << "range_noise_m" << YAML::Value << s.laser.range_noise_m;
  out << YAML::Key << "max_range_m" << YAML::Value << s.laser.max_range_m;
  out << YAML::Key << "dropout_probability" << YAML::Value << s.laser.dropout_probability;
  out << YAML::Key << "sweep" << YAML::Value << s.laser.sweep;
  out << YAML::Key << "range_noise_per_m" << YAML::Value << s.laser.range_noise_per_m;
  if (s.laser.range_noise_correlation > 0.0)  // only then: other truth files stay as they were
    out << YAML::Key << "range_noise_correlation" << YAML::Value << s.laser.range_noise_correlation;
  out << YAML::Key << "range_resolution_m" << YAML::Value << s.laser.range_resolution_m;
  out << YAML::Key << "mixed_pixel_probability" << YAML::Value << s.laser.mixed_pixel_probability;
  out << YAML::Key << "beam_divergence_rad" << YAML::Value << s.laser.beam_divergence_rad;
  out << YAML::Key << "dark_dropout_probability" << YAML::Value << s.laser.dark_dropout_probability;
  if (s.laser.range_ripple_m >
      0.0) {  // only then: truth files of other scenarios stay as they were
    out << YAML::Key << "range_ripple_m" << YAML::Value << s.laser.range_ripple_m;
    out << YAML::Key << "range_ripple_period_rays" << YAML::Value
        << s.laser.range_ripple_period_rays;
  }
  out << YAML::Key << "frame_id" << YAML::Value << s.laser.frame_id;
  out << YAML::Key << "topic" << YAML::Value << s.laser.topic;
  out << YAML::Key << "type" << YAML::Value << s.laser.type;
  if (s.laser.type == "multibeam") {
    out << YAML::Key << "rings" << YAML::Value << s.laser.rings;
    out << YAML::Key << "elevation_min_rad" << YAML::Value << s.laser.elevation_min_rad;
    out << YAML::Key << "elevation_max_rad" << YAML::Value << s.laser.elevation_max_rad;
    out << YAML::Key << "horizontal_step_rad" << YAML::Value << s.laser.horizontal_step_rad;
    out << YAML::Key << "height_m" << YAML::Value << s.laser.height_m;
    out << YAML::Key << "roll_rad" << YAML::Value << s.laser.roll_rad;
    out << YAML::Key << "pitch_rad" << YAML::Value << s.laser.pitch_rad;
    out << YAML::Key << "point_times" << YAML::Value << s.laser.point_times;
  }
  out << YAML::EndMap;
  out << YAML::Key << "encoders" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rate_hz" << YAML::Value << s.encoders.rate_hz;
  out << YAML::Key << "topic" << YAML::Value << s.encoders.topic;
  out << YAML::Key << "units" << YAML::Value << (s.encoders.output_ticks ? "ticks" : "radians");
  out << YAML::Key << "counter_bits" << YAML::Value << s.encoders.counter_bits;
  out << YAML::Key << "initial_ticks" << YAML::Value << s.encoders.initial_ticks;
  out << YAML::Key << "time_offset_s" << YAML::Value << s.encoders.time_offset_s;
  out << YAML::EndMap;
  out << YAML::Key << "tracker" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "enabled" << YAML::Value << s.tracker.enabled;
  out << YAML::Key << "translation_noise_m" << YAML::Value << s.tracker.translation_noise_m;
  out << YAML::Key << "rotation_noise_rad" << YAML::Value << s.tracker.rotation_noise_rad;
  out << YAML::Key << "topic" << YAML::Value << s.tracker.topic;
  out << YAML::EndMap;
  out << YAML::Key << "ground_truth_topic" << YAML::Value << s.ground_truth_topic;
  out << YAML::Key << "ground_truth_frame" << YAML::Value << s.ground_truth_frame;
  if (!s.changes.empty()) {
    // The robot and laser change mid-run: the parameters above hold until the first change.
    out << YAML::Key << "changes" << YAML::Value << YAML::BeginSeq;
    for (const ParameterChange& change : s.changes) {
      out << YAML::BeginMap;
      out << YAML::Key << "at_s" << YAML::Value << change.at_s;
      if (!change.robot_parameters.empty()) {
        out << YAML::Key << "robot" << YAML::Value << YAML::BeginMap;
        for (const auto& [key, value] : change.robot_parameters)
          out << YAML::Key << key << YAML::Value << value;
        out << YAML::EndMap;
      }
      out << YAML::Key << "laser_yaw_change_rad" << YAML::Value << change.laser_yaw_change_rad;
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  return "# odometry_calibration simulator: true parameters of this run\n" +
         std::string(out.c_str()) + "\n";
}

Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory,
                          const ScenarioOverrides& overrides)
{
  Scenario scenario = loadScenarioYaml(path, worlds_directory);
  if (overrides.seed >= 0.0)
    scenario.seed = static_cast<unsigned>(overrides.seed);
  if (overrides.duration_s > 0.0)
    scenario.duration_s = overrides.duration_s;
  return scenario;
}

std::string shippedWorldsDirectory()
{
  return std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds";
}
}  // namespace sim
}  // namespace odometry_calibration
