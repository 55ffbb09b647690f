// The live node's own parameters (~name), read and checked.
#include "odometry_calibration/live_node/calibration_node.h"

namespace odometry_calibration {
namespace {

/// The live assistant's ~guidance_* and ~health_* parameters.
void readAssistantOptions(const ros::NodeHandle& p, SessionAssistantOptions* o)
{
  ExcitationGuidanceOptions& g = o->guidance_options;
  HealthMonitorOptions& h = o->health_options;
  p.param("guidance", o->guidance, o->guidance);
  p.param("guidance_relative_target", g.relative_target, g.relative_target);
  p.param("guidance_length_target_m", g.length_target_m, g.length_target_m);
  p.param("guidance_angle_target_rad", g.angle_target_rad, g.angle_target_rad);
  p.param("guidance_straight_distance_m", g.straight_distance_m, g.straight_distance_m);
  p.param("guidance_spot_turn_rad", g.spot_turn_rad, g.spot_turn_rad);
  p.param("guidance_turn_rad", g.turn_rad, g.turn_rad);
  p.param("guidance_strafe_distance_m", g.strafe_distance_m, g.strafe_distance_m);
  p.param("guidance_full_lock_rad", g.full_lock_rad, g.full_lock_rad);
  p.param("guidance_full_lock_travel_m", g.full_lock_travel_m, g.full_lock_travel_m);
  std::map<std::string, double> targets;
  if (p.getParam("guidance_target_sigma", targets))
    g.target_sigma = targets;
  else if (p.hasParam("guidance_target_sigma"))
    throw std::invalid_argument(
        "~guidance_target_sigma must map parameter names to sigmas, e.g. {wheel_separation: "
        "0.0005}");
  p.param("health_monitor", o->health_monitor, o->health_monitor);
  p.param("health_false_alarm_pairs", h.false_alarm_pairs, h.false_alarm_pairs);
  p.param("health_design_shift_sigma", h.design_shift_sigma, h.design_shift_sigma);
  p.param("health_burn_in_pairs", h.burn_in_pairs, h.burn_in_pairs);
  try {
    validate(g);
    validate(h);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("~guidance_* / ~health_* parameters: ") + error.what());
  }
}

/// Throws std::invalid_argument naming the first bad parameter.
void check(const NodeOptions& o)
{
  const SessionOptions& s = o.session;
  auto require = [](bool ok, const char* what) {
    if (!ok)
      throw std::invalid_argument(what);
  };
  require(!o.config_path.empty(),
          "~config is required: the calibration YAML (e.g. $(find odometry_calibration)/config/"
          "diff_drive.yaml)");
  require(!o.odom_frame.empty() && !o.base_frame.empty(),
          "~odom_frame and ~base_frame must not be empty");
  require(s.silent_topic_timeout_s > 0.0, "~silent_topic_timeout_s must be > 0 s");
  require(s.min_pairs >= 1, "~min_pairs must be >= 1");
  require(s.odometry_options.path_spacing_s >= 0.0, "~path_spacing_s must be >= 0 s");
  require(s.odometry_options.path_max_poses >= 2, "~path_max_poses must be >= 2");
  require(o.diagnostics_period_s > 0.0, "~diagnostics_period_s must be > 0 s");
  require(o.holdout_fraction >= 0.0 && o.holdout_fraction < 1.0,
          "~holdout_fraction must be in [0, 1) (0: no held-out table in the ~calibrate reply)");
  require(o.marker_height_m >= 0.0 && o.marker_text_height_m > 0.0,
          "~guidance_marker_height_m must be >= 0 m and ~guidance_marker_text_m > 0 m");
}

}  // namespace

NodeOptions readNodeOptions(const ros::NodeHandle& p)
{
  NodeOptions o;
  SessionOptions& s = o.session;
  p.param("config", o.config_path, o.config_path);
  p.param("output_directory", s.output_directory, s.output_directory);
  p.param("odom_frame", o.odom_frame, o.odom_frame);
  p.param("base_frame", o.base_frame, o.base_frame);
  p.param("sensor_frame", o.sensor_frame, o.sensor_frame);
  p.param("publish_odom_tf", o.publish_odom_tf, o.publish_odom_tf);
  p.param("publish_extrinsic_tf", o.publish_extrinsic_tf, o.publish_extrinsic_tf);
  p.param("load_saved_calibration", s.load_saved_calibration, s.load_saved_calibration);
  p.param("resume_pairs", s.resume_pairs, s.resume_pairs);
  p.param("silent_topic_timeout_s", s.silent_topic_timeout_s, s.silent_topic_timeout_s);
  p.param("min_pairs", s.min_pairs, s.min_pairs);
  p.param("path_spacing_s", s.odometry_options.path_spacing_s, s.odometry_options.path_spacing_s);
  p.param("path_max_poses", s.odometry_options.path_max_poses, s.odometry_options.path_max_poses);
  p.param("diagnostics_period_s", o.diagnostics_period_s, o.diagnostics_period_s);
  p.param("guidance_marker_height_m", o.marker_height_m, o.marker_height_m);
  p.param("guidance_marker_text_m", o.marker_text_height_m, o.marker_text_height_m);
  p.param("holdout_fraction", o.holdout_fraction, o.holdout_fraction);
  readAssistantOptions(p, &s.assistant_options);
  check(o);
  return o;
}

}  // namespace odometry_calibration
