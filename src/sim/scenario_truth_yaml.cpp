#include "odometry_calibration/sim/scenario.h"

#include <string>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {
namespace sim {
namespace {

/// robot: the type and the true parameters; joints: each encoder's name, kind and resolution.
void emitRobot(const Scenario& s, const Robot& robot, YAML::Emitter& out)
{
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
}

/// The laser's noise model (the correlation and the ripple only when present: the truth files
/// of other scenarios stay as they were).
void emitLaserNoise(const LaserOptions& laser, YAML::Emitter& out)
{
  out << YAML::Key << "rays" << YAML::Value << laser.rays;
  out << YAML::Key << "fov_rad" << YAML::Value << laser.fov_rad;
  out << YAML::Key << "rate_hz" << YAML::Value << laser.rate_hz;
  out << YAML::Key << "range_noise_m" << YAML::Value << laser.range_noise_m;
  out << YAML::Key << "max_range_m" << YAML::Value << laser.max_range_m;
  out << YAML::Key << "dropout_probability" << YAML::Value << laser.dropout_probability;
  out << YAML::Key << "sweep" << YAML::Value << laser.sweep;
  out << YAML::Key << "range_noise_per_m" << YAML::Value << laser.range_noise_per_m;
  if (laser.range_noise_correlation > 0.0)  // only then: other truth files stay as they were
    out << YAML::Key << "range_noise_correlation" << YAML::Value << laser.range_noise_correlation;
  out << YAML::Key << "range_resolution_m" << YAML::Value << laser.range_resolution_m;
  out << YAML::Key << "mixed_pixel_probability" << YAML::Value << laser.mixed_pixel_probability;
  out << YAML::Key << "beam_divergence_rad" << YAML::Value << laser.beam_divergence_rad;
  out << YAML::Key << "dark_dropout_probability" << YAML::Value << laser.dark_dropout_probability;
  if (laser.range_ripple_m > 0.0) {  // only then: truth files of other scenarios stay as they were
    out << YAML::Key << "range_ripple_m" << YAML::Value << laser.range_ripple_m;
    out << YAML::Key << "range_ripple_period_rays" << YAML::Value << laser.range_ripple_period_rays;
  }
}

/// T_base_laser, and laser: the sensor model, names, type and a multibeam lidar's geometry.
void emitLaser(const LaserOptions& laser, YAML::Emitter& out)
{
  const Pose2& T = laser.T_base_laser;
  out << YAML::Key << "T_base_laser" << YAML::Value << YAML::BeginMap << YAML::Key << "x"
      << YAML::Value << T.x() << YAML::Key << "y" << YAML::Value << T.y() << YAML::Key << "theta"
      << YAML::Value << T.theta() << YAML::EndMap;
  out << YAML::Key << "laser" << YAML::Value << YAML::BeginMap;
  emitLaserNoise(laser, out);
  out << YAML::Key << "frame_id" << YAML::Value << laser.frame_id;
  out << YAML::Key << "topic" << YAML::Value << laser.topic;
  out << YAML::Key << "type" << YAML::Value << laser.type;
  if (laser.time_offset_s != 0.0)  // only then: truth files of other scenarios stay as they were
    out << YAML::Key << "time_offset_s" << YAML::Value << laser.time_offset_s;
  if (laser.type == "multibeam") {
    out << YAML::Key << "rings" << YAML::Value << laser.rings;
    out << YAML::Key << "elevation_min_rad" << YAML::Value << laser.elevation_min_rad;
    out << YAML::Key << "elevation_max_rad" << YAML::Value << laser.elevation_max_rad;
    out << YAML::Key << "horizontal_step_rad" << YAML::Value << laser.horizontal_step_rad;
    out << YAML::Key << "height_m" << YAML::Value << laser.height_m;
    out << YAML::Key << "roll_rad" << YAML::Value << laser.roll_rad;
    out << YAML::Key << "pitch_rad" << YAML::Value << laser.pitch_rad;
    out << YAML::Key << "point_times" << YAML::Value << laser.point_times;
  }
  out << YAML::EndMap;
}

/// encoders and tracker.
void emitEncodersAndTracker(const Scenario& s, YAML::Emitter& out)
{
  out << YAML::Key << "encoders" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rate_hz" << YAML::Value << s.encoders.rate_hz;
  out << YAML::Key << "rate_jitter_s" << YAML::Value << s.encoders.rate_jitter_s;
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
}

/// changes: the robot, the laser's mounting and the encoders' clock change mid-run (the values
/// above hold until the first).
void emitChanges(const std::vector<ParameterChange>& changes, YAML::Emitter& out)
{
  out << YAML::Key << "changes" << YAML::Value << YAML::BeginSeq;
  for (const ParameterChange& change : changes) {
    out << YAML::BeginMap;
    out << YAML::Key << "at_s" << YAML::Value << change.at_s;
    if (!change.robot_parameters.empty()) {
      out << YAML::Key << "robot" << YAML::Value << YAML::BeginMap;
      for (const auto& [key, value] : change.robot_parameters)
        out << YAML::Key << key << YAML::Value << value;
      out << YAML::EndMap;
    }
    if (change.laser_index != 0)  // the first laser unless said (one-laser truths unchanged)
      out << YAML::Key << "laser" << YAML::Value << change.laser_index;
    out << YAML::Key << "laser_x_change_m" << YAML::Value << change.laser_x_change_m;
    out << YAML::Key << "laser_y_change_m" << YAML::Value << change.laser_y_change_m;
    out << YAML::Key << "laser_yaw_change_rad" << YAML::Value << change.laser_yaw_change_rad;
    out << YAML::Key << "time_offset_change_s" << YAML::Value << change.time_offset_change_s;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

}  // namespace

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
  emitRobot(s, robot, out);
  emitLaser(s.laser, out);
  if (!s.extra_lasers.empty()) {  // each further laser's true pose and sensor model
    out << YAML::Key << "extra_lasers" << YAML::Value << YAML::BeginSeq;
    for (const LaserOptions& laser : s.extra_lasers) {
      out << YAML::BeginMap;
      emitLaser(laser, out);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  emitEncodersAndTracker(s, out);
  out << YAML::Key << "ground_truth_topic" << YAML::Value << s.ground_truth_topic;
  out << YAML::Key << "ground_truth_frame" << YAML::Value << s.ground_truth_frame;
  if (!s.changes.empty()) {
    emitChanges(s.changes, out);
  }
  out << YAML::EndMap;
  return "# odometry_calibration simulator: true parameters of this run\n" +
         std::string(out.c_str()) + "\n";
}

}  // namespace sim
}  // namespace odometry_calibration
