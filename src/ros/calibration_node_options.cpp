// The live node's own parameters (~name), read and checked.
#include "odometry_calibration/ros/calibration_node.h"

namespace odometry_calibration {

NodeOptions readNodeOptions(const ros::NodeHandle& p)
{
  NodeOptions o;
  p.param("config", o.config_path, o.config_path);
  p.param("output_directory", o.output_directory, o.output_directory);
  p.param("odom_frame", o.odom_frame, o.odom_frame);
  p.param("base_frame", o.base_frame, o.base_frame);
  p.param("sensor_frame", o.sensor_frame, o.sensor_frame);
  p.param("publish_odom_tf", o.publish_odom_tf, o.publish_odom_tf);
  p.param("publish_extrinsic_tf", o.publish_extrinsic_tf, o.publish_extrinsic_tf);
  p.param("load_saved_calibration", o.load_saved_calibration, o.load_saved_calibration);
  p.param("resume_pairs", o.resume_pairs, o.resume_pairs);
  p.param("silent_topic_timeout_s", o.silent_topic_timeout_s, o.silent_topic_timeout_s);
  p.param("min_pairs", o.min_pairs, o.min_pairs);
  p.param("path_spacing_s", o.path_spacing_s, o.path_spacing_s);
  p.param("path_max_poses", o.path_max_poses, o.path_max_poses);
  p.param("diagnostics_period_s", o.diagnostics_period_s, o.diagnostics_period_s);
  if (o.config_path.empty()) {
    throw std::invalid_argument(
        "~config is required: the calibration YAML (e.g. $(find odometry_calibration)/config/"
        "diff_drive.yaml)");
  }
  if (o.odom_frame.empty() || o.base_frame.empty())
    throw std::invalid_argument("~odom_frame and ~base_frame must not be empty");
  if (!(o.silent_topic_timeout_s > 0.0))
    throw std::invalid_argument("~silent_topic_timeout_s must be > 0 s");
  if (o.min_pairs < 1)
    throw std::invalid_argument("~min_pairs must be >= 1");
  if (!(o.path_spacing_s >= 0.0))
    throw std::invalid_argument("~path_spacing_s must be >= 0 s");
  if (o.path_max_poses < 2)
    throw std::invalid_argument("~path_max_poses must be >= 2");
  if (!(o.diagnostics_period_s > 0.0))
    throw std::invalid_argument("~diagnostics_period_s must be > 0 s");
  return o;
}

}  // namespace odometry_calibration
