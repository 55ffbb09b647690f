#include "odometry_calibration/calibration/calibration_config.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/common/yaml_reading.h"

#include "odometry_calibration/gp/gp_options.h"

namespace odometry_calibration {
namespace {

int jointIndex(const CalibrationConfig& config, const std::string& name, const std::string& key)
{
  for (std::size_t j = 0; j < config.joints.size(); ++j) {
    if (config.joints[j].name == name)
      return static_cast<int>(j);
  }
  throw std::runtime_error(key + ": no joint named '" + name + "' among 'joints'");
}

/// A model section's `sensor_pose: [x_m, y_m, theta_rad]` (the origin when absent).
Pose2 readSensorPose(const YAML::Node& section)
{
  std::vector<double> pose = {0.0, 0.0, 0.0};
  readYaml(section, "sensor_pose", &pose);
  if (pose.size() != 3)
    throw std::runtime_error("sensor_pose needs [x_m, y_m, theta_rad]");
  return Pose2(pose[0], pose[1], pose[2]);
}

/// The `skid_steer` section: the joints of each side (default: the incremental joints whose
/// names contain "left" / "right"), the geometric radius and track width, the fit's options.
/// The joints are resolved and checked only when the configuration uses the model (`used`).
void readSkidSteer(const YAML::Node& section, bool used, const std::string& where,
                   CalibrationConfig* c)
{
  checkYamlKeys(section,
                {"left_joints", "right_joints", "wheel_radius_m", "wheel_separation_m",
                 "sensor_pose", "huber_threshold", "max_iterations", "yaw_starts"},
                where);
  SkidSteerOptions& s = c->models.skid_steer;
  std::vector<std::string> left, right;
  for (const JointConfig& joint : c->joints) {
    if (joint.kind != EncoderKind::kIncremental)
      continue;
    if (joint.name.find("left") != std::string::npos)
      left.push_back(joint.name);
    else if (joint.name.find("right") != std::string::npos)
      right.push_back(joint.name);
  }
  readYaml(section, "left_joints", &left);
  readYaml(section, "right_joints", &right);
  readYaml(section, "wheel_radius_m", &s.wheel_radius_m);
  readYaml(section, "wheel_separation_m", &s.wheel_separation_m);
  readYaml(section, "huber_threshold", &s.huber_threshold);
  readYaml(section, "max_iterations", &s.max_iterations);
  readYaml(section, "yaw_starts", &s.yaw_starts);
  s.initial_T_base_sensor = readSensorPose(section);
  if (!used)
    return;
  if (left.empty() || right.empty()) {
    throw std::runtime_error(
        "left_joints and right_joints are required (no incremental joint named *left* / "
        "*right* to default to)");
  }
  s.left_indices.clear();
  s.right_indices.clear();
  for (const std::string& name : left)
    s.left_indices.push_back(jointIndex(*c, name, where + ".left_joints"));
  for (const std::string& name : right)
    s.right_indices.push_back(jointIndex(*c, name, where + ".right_joints"));
  s.ticks_per_turn = c->joints[s.left_indices.front()].units_per_turn;
  for (const std::vector<int>* side : {&s.left_indices, &s.right_indices}) {
    for (int index : *side) {
      if (c->joints[index].kind != EncoderKind::kIncremental ||
          c->joints[index].units_per_turn != s.ticks_per_turn) {
        throw std::runtime_error(
            "the wheel joints must be incremental with the same units_per_turn");
      }
    }
  }
  try {
    validate(s);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(error.what());
  }
}

}  // namespace

CalibrationConfig parseCalibrationConfig(const std::string& text, const std::string& source)
{
  CalibrationConfig c;
  std::string where = source;
  try {
    const YAML::Node root = YAML::Load(text);
    checkYamlKeys(root,
                  {"joints", "joint_state_topic", "ego_motion", "keyframes", "scan_matching",
                   "model", "compare_models", "prior_model", "diff_drive", "linear", "gp",
                   "tricycle", "mecanum", "output_directory", "skid_steer"},
                  source);
    where = source + ": joints";
    if (!root["joints"] || !root["joints"].IsSequence() || root["joints"].size() == 0) {
      throw std::runtime_error("a list of joints is required");
    }
    for (const YAML::Node& node : root["joints"]) {
      where = source + ": joints[" + std::to_string(c.joints.size()) + "]";
      checkYamlKeys(node,
                    {"name", "kind", "units_per_turn", "counter_bits", "sign", "max_turns_per_s"},
                    where);
      JointConfig joint;
      readYaml(node, "name", &joint.name);
      std::string kind = "incremental";
      readYaml(node, "kind", &kind);
      if (kind != "incremental" && kind != "absolute") {
        throw std::runtime_error("kind must be 'incremental' or 'absolute', got '" + kind + "'");
      }
      joint.kind = kind == "incremental" ? EncoderKind::kIncremental : EncoderKind::kAbsolute;
      readYaml(node, "units_per_turn", &joint.units_per_turn);
      readYaml(node, "counter_bits", &joint.counter_bits);
      readYaml(node, "sign", &joint.sign);
      readYaml(node, "max_turns_per_s", &joint.max_turns_per_s);
      if (joint.name.empty())
        throw std::runtime_error("name is required");
      if (!(joint.units_per_turn > 0.0))
        throw std::runtime_error("units_per_turn must be > 0");
      if (joint.counter_bits < 0 || joint.counter_bits > 52) {
        throw std::runtime_error("counter_bits must be in [0, 52]");
      }
      if (!std::isfinite(joint.max_turns_per_s) || joint.max_turns_per_s < 0.0)
        throw std::runtime_error("max_turns_per_s must be >= 0 (0 = no glitch check)");
      if (joint.sign != 1.0 && joint.sign != -1.0)
        throw std::runtime_error("sign must be 1 or -1");
      c.joints.push_back(joint);
    }
    where = source;
    readYaml(root, "joint_state_topic", &c.joint_state_topic);
    readYaml(root, "model", &c.model);
    readYaml(root, "compare_models", &c.compare_models);
    // The matcher's guesses come from the fitted model's own start values when it has some.
    if (c.model == "tricycle" || c.model == "mecanum" || c.model == "skid_steer")
      c.prior_model = c.model;
    readYaml(root, "prior_model", &c.prior_model);
    readYaml(root, "output_directory", &c.output_directory);

    where = source + ": ego_motion";
    const YAML::Node ego = root["ego_motion"];
    checkYamlKeys(ego, {"source", "scan_topic", "topic", "sigma_m", "sigma_rad", "cloud"}, where);
    std::string kind = "scan";
    readYaml(ego, "source", &kind);
    if (kind == "scan") {
      c.ego_motion = EgoMotionSource::kScan;
    } else if (kind == "odometry") {
      c.ego_motion = EgoMotionSource::kOdometry;
    } else if (kind == "pose") {
      c.ego_motion = EgoMotionSource::kPose;
    } else if (kind == "cloud") {
      c.ego_motion = EgoMotionSource::kCloud;
    } else {
      throw std::runtime_error("source must be scan, cloud, odometry or pose, got '" + kind + "'");
    }
    readYaml(ego, "scan_topic", &c.scan_topic);
    readYaml(ego, "topic", &c.ego_motion_topic);
    readYaml(ego, "sigma_m", &c.ego_motion_sigma_m);
    readYaml(ego, "sigma_rad", &c.ego_motion_sigma_rad);
    if (c.ego_motion != EgoMotionSource::kScan && c.ego_motion_topic.empty()) {
      throw std::runtime_error("source '" + kind + "' needs 'topic'");
    }
    where = source + ": ego_motion.cloud";
    if (ego && ego["cloud"]) {
      const YAML::Node cloud = ego["cloud"];
      checkYamlKeys(
          cloud,
          {"band_m", "roll_rad", "pitch_rad", "voxel_size_m", "outlier_neighbours",
           "outlier_stddev", "angular_resolution_rad", "range_min_m", "range_max_m", "scan_from",
           "point_time_field", "point_time_unit", "point_time_reference", "point_time_limit_s"},
          where);
      CloudToScanOptions& o = c.cloud;
      if (cloud["band_m"]) {
        std::vector<double> band;
        readYaml(cloud, "band_m", &band);
        if (band.size() != 2)
          throw std::runtime_error("band_m must be [min, max] in metres");
        o.band_min_m = band[0];
        o.band_max_m = band[1];
      }
      readYaml(cloud, "roll_rad", &o.roll_rad);
      readYaml(cloud, "pitch_rad", &o.pitch_rad);
      readYaml(cloud, "voxel_size_m", &o.voxel_size_m);
      readYaml(cloud, "outlier_neighbours", &o.outlier_neighbours);
      readYaml(cloud, "outlier_stddev", &o.outlier_stddev);
      readYaml(cloud, "angular_resolution_rad", &o.angular_resolution_rad);
      readYaml(cloud, "range_min_m", &o.range_min_m);
      readYaml(cloud, "range_max_m", &o.range_max_m);
      std::string name = toString(o.scan_from);
      readYaml(cloud, "scan_from", &name);
      o.scan_from = scanFromName(name);
      readYaml(cloud, "point_time_field", &o.point_times.field);
      name = toString(o.point_times.unit);
      readYaml(cloud, "point_time_unit", &name);
      o.point_times.unit = pointTimeUnitName(name);
      name = toString(o.point_times.reference);
      readYaml(cloud, "point_time_reference", &name);
      o.point_times.reference = pointTimeReferenceName(name);
      readYaml(cloud, "point_time_limit_s", &o.point_times.limit_s);
    }

    where = source + ": keyframes";
    const YAML::Node keyframes = root["keyframes"];
    checkYamlKeys(keyframes,
                  {"interval_s", "min_translation_m", "min_rotation_rad", "time_offset_s",
                   "max_encoder_gap_s", "check_consistency", "consistency_translation_m",
                   "consistency_rotation_rad", "estimate_time_offset", "time_offset_search_s",
                   "fit_intervals_s"},
                  where);
    CollectorOptions& k = c.collector;
    readYaml(keyframes, "interval_s", &k.keyframe_interval_s);
    readYaml(keyframes, "min_translation_m", &k.min_translation_m);
    readYaml(keyframes, "min_rotation_rad", &k.min_rotation_rad);
    readYaml(keyframes, "time_offset_s", &k.time_offset_s);
    readYaml(keyframes, "max_encoder_gap_s", &k.max_encoder_gap_s);
    readYaml(keyframes, "check_consistency", &k.check_consistency);
    readYaml(keyframes, "consistency_translation_m", &k.consistency_translation_m);
    readYaml(keyframes, "consistency_rotation_rad", &k.consistency_rotation_rad);
    readYaml(keyframes, "estimate_time_offset", &c.estimate_time_offset);
    if (keyframes && keyframes["time_offset_search_s"]) {
      const auto range = keyframes["time_offset_search_s"].as<std::vector<double>>();
      if (range.size() != 2 || !(range[1] > range[0])) {
        throw std::runtime_error("time_offset_search_s needs [min, max] with min < max");
      }
      c.time_offset_search_min_s = range[0];
      c.time_offset_search_max_s = range[1];
    }
    if (keyframes && keyframes["fit_intervals_s"]) {
      c.fit_intervals_s = keyframes["fit_intervals_s"].as<std::vector<double>>();
      for (std::size_t i = 0; i < c.fit_intervals_s.size(); ++i) {
        const double interval = c.fit_intervals_s[i];
        if (!(interval > 0.0) || !(interval <= 60.0) ||
            (i > 0 && !(interval > c.fit_intervals_s[i - 1]))) {
          throw std::runtime_error(
              "fit_intervals_s: candidate intervals must increase, each in (0, 60] s");
        }
      }
    }

    where = source + ": scan_matching";
    const YAML::Node matching = root["scan_matching"];
    checkYamlKeys(matching,
                  {"max_correspondence_distance_m", "max_iterations", "range_sigma_m",
                   "max_correction_translation_m", "max_correction_rotation_rad", "min_points",
                   "compensate_sweep", "segment_fallback_max_surface_points",
                   "veiling_min_angle_rad", "trim_keep_fraction"},
                  where);
    PlicpOptions& p = k.plicp;
    readYaml(matching, "max_correspondence_distance_m", &p.max_correspondence_distance_m);
    readYaml(matching, "max_iterations", &p.max_iterations);
    readYaml(matching, "range_sigma_m", &p.range_sigma_m);
    readYaml(matching, "max_correction_translation_m", &p.max_correction_translation_m);
    readYaml(matching, "max_correction_rotation_rad", &p.max_correction_rotation_rad);
    readYaml(matching, "min_points", &p.min_points);
    readYaml(matching, "compensate_sweep", &k.compensate_sweep);
    readYaml(matching, "segment_fallback_max_surface_points",
             &p.line_fit.segment_fallback_max_surface_points);
    readYaml(matching, "veiling_min_angle_rad", &p.line_fit.veiling_min_angle_rad);
    readYaml(matching, "trim_keep_fraction", &p.trim_keep_fraction);
    validate(k);
    // A cloud is rejected where its scan would be: with fewer rays than the matcher needs.
    c.cloud.min_points = static_cast<std::size_t>(std::max(1, p.min_points));
    where = source + ": ego_motion.cloud";
    validate(c.cloud);

    where = source + ": diff_drive";
    const YAML::Node diff = root["diff_drive"];
    checkYamlKeys(diff,
                  {"left_joint", "right_joint", "wheel_radius_m", "wheel_separation_m",
                   "sensor_pose", "huber_threshold", "max_iterations", "yaw_starts"},
                  where);
    DiffDriveOptions& d = c.models.diff_drive;
    std::string left = c.joints[0].name;
    std::string right = c.joints.size() > 1 ? c.joints[1].name : "";
    readYaml(diff, "left_joint", &left);
    readYaml(diff, "right_joint", &right);
    double radius = 0.05;
    readYaml(diff, "wheel_radius_m", &radius);
    d.initial_left_radius_m = d.initial_right_radius_m = radius;
    readYaml(diff, "wheel_separation_m", &d.initial_separation_m);
    readYaml(diff, "huber_threshold", &d.huber_threshold);
    readYaml(diff, "max_iterations", &d.max_iterations);
    readYaml(diff, "yaw_starts", &d.yaw_starts);
    d.initial_T_base_sensor = readSensorPose(diff);
    if (c.model == "diff_drive" || c.prior_model == "diff_drive" ||
        std::find(c.compare_models.begin(), c.compare_models.end(), "diff_drive") !=
            c.compare_models.end()) {
      d.layout.left_index = jointIndex(c, left, where + ".left_joint");
      d.layout.right_index = jointIndex(c, right, where + ".right_joint");
      if (c.joints[d.layout.left_index].units_per_turn !=
          c.joints[d.layout.right_index].units_per_turn) {
        throw std::runtime_error("the two wheels need the same units_per_turn");
      }
      d.layout.ticks_per_turn = c.joints[d.layout.left_index].units_per_turn;
      validate(d);
    }

    auto uses = [&c](const std::string& model) {
      if (c.model == model || c.prior_model == model)
        return true;
      for (const std::string& name : c.compare_models)
        if (name == model)
          return true;
      return false;
    };
    where = source + ": tricycle";
    const YAML::Node tri = root["tricycle"];
    checkYamlKeys(
        tri,
        {"steering_joint", "traction_joint", "steering_scale", "traction_scale_m_per_turn",
         "axis_length_m", "steering_offset_rad", "sensor_pose", "huber_threshold",
         "translation_sigma_m", "rotation_sigma_rad", "max_iterations", "yaw_starts"},
        where);
    TricycleModelOptions& t = c.models.tricycle;
    std::string steering = c.joints[0].name;
    std::string traction = c.joints.size() > 1 ? c.joints[1].name : "";
    readYaml(tri, "steering_joint", &steering);
    readYaml(tri, "traction_joint", &traction);
    readYaml(tri, "steering_scale", &t.initial.steering_scale);
    readYaml(tri, "traction_scale_m_per_turn", &t.initial.traction_scale_m_per_turn);
    readYaml(tri, "axis_length_m", &t.initial.axis_length_m);
    readYaml(tri, "steering_offset_rad", &t.initial.steering_offset_rad);
    readYaml(tri, "huber_threshold", &t.calibration.huber_threshold);
    readYaml(tri, "translation_sigma_m", &t.calibration.translation_sigma_m);
    readYaml(tri, "rotation_sigma_rad", &t.calibration.rotation_sigma_rad);
    readYaml(tri, "max_iterations", &t.calibration.max_iterations);
    readYaml(tri, "yaw_starts", &t.calibration.yaw_starts);
    t.initial.T_base_sensor = readSensorPose(tri);
    if (uses("tricycle")) {
      t.layout.steering_index = jointIndex(c, steering, where + ".steering_joint");
      t.layout.traction_index = jointIndex(c, traction, where + ".traction_joint");
      if (c.joints[t.layout.steering_index].kind != EncoderKind::kAbsolute ||
          c.joints[t.layout.traction_index].kind != EncoderKind::kIncremental) {
        throw std::runtime_error(
            "the steering joint must be kind: absolute and the traction joint incremental");
      }
      t.layout.steering_ticks_per_turn = c.joints[t.layout.steering_index].units_per_turn;
      t.layout.traction_ticks_per_turn = c.joints[t.layout.traction_index].units_per_turn;
      validate(t.calibration);
      validateStartValues(t.initial);
    }

    where = source + ": mecanum";
    const YAML::Node mec = root["mecanum"];
    checkYamlKeys(mec,
                  {"front_left_joint", "front_right_joint", "rear_left_joint", "rear_right_joint",
                   "wheel_radius_m", "wheel_radii_m", "lx_plus_ly_m", "sensor_pose",
                   "huber_threshold", "max_iterations", "yaw_starts"},
                  where);
    MecanumOptions& m = c.models.mecanum;
    std::array<std::string, 4> wheels;
    const char* wheel_keys[4] = {"front_left_joint", "front_right_joint", "rear_left_joint",
                                 "rear_right_joint"};
    for (std::size_t i = 0; i < 4; ++i) {
      wheels[i] = i < c.joints.size() ? c.joints[i].name : "";
      readYaml(mec, wheel_keys[i], &wheels[i]);
    }
    double mecanum_radius = 0.05;
    readYaml(mec, "wheel_radius_m", &mecanum_radius);
    m.initial_radius_m.fill(mecanum_radius);
    if (mec && mec["wheel_radii_m"]) {
      const auto radii = mec["wheel_radii_m"].as<std::vector<double>>();
      if (radii.size() != 4)
        throw std::runtime_error(
            "wheel_radii_m needs [front_left, front_right, rear_left, "
            "rear_right] in m");
      std::copy(radii.begin(), radii.end(), m.initial_radius_m.begin());
    }
    readYaml(mec, "lx_plus_ly_m", &m.initial_lx_plus_ly_m);
    readYaml(mec, "huber_threshold", &m.huber_threshold);
    readYaml(mec, "max_iterations", &m.max_iterations);
    readYaml(mec, "yaw_starts", &m.yaw_starts);
    m.initial_T_base_sensor = readSensorPose(mec);
    if (uses("mecanum")) {
      if (c.joints.size() < 4)
        throw std::runtime_error("mecanum needs four wheel joints among 'joints'");
      int* index[4] = {&m.layout.front_left_index, &m.layout.front_right_index,
                       &m.layout.rear_left_index, &m.layout.rear_right_index};
      for (std::size_t i = 0; i < 4; ++i) {
        *index[i] = jointIndex(c, wheels[i], where + "." + wheel_keys[i]);
        const JointConfig& joint = c.joints[static_cast<std::size_t>(*index[i])];
        if (joint.kind != EncoderKind::kIncremental)
          throw std::runtime_error(std::string(wheel_keys[i]) + ": '" + joint.name +
                                   "' must be kind: incremental");
        if (joint.units_per_turn != c.joints[static_cast<std::size_t>(*index[0])].units_per_turn)
          throw std::runtime_error("the four wheels need the same units_per_turn");
      }
      m.layout.ticks_per_turn = c.joints[static_cast<std::size_t>(*index[0])].units_per_turn;
      validate(m);
    }
    where = source + ": skid_steer";
    readSkidSteer(root["skid_steer"], uses("skid_steer"), where, &c);

    where = source + ": linear";
    const YAML::Node linear = root["linear"];
    checkYamlKeys(linear, {"huber_threshold", "outlier_threshold"}, where);
    readYaml(linear, "huber_threshold", &c.models.linear.huber_threshold);
    readYaml(linear, "outlier_threshold", &c.models.linear.outlier_threshold);
    c.models.joints = jointLayout(c);

    where = source + ": gp";
    const YAML::Node gp = root["gp"];
    checkYamlKeys(
        gp, {"kernel", "mean", "starts", "max_exact_pairs", "inducing_points", "outlier_threshold"},
        where);
    if (gp && gp["kernel"])
      c.models.gp.kernel = parseGpKernelType(gp["kernel"].as<std::string>());
    if (gp && gp["mean"])
      c.models.gp.mean = parseGpMeanFunction(gp["mean"].as<std::string>());
    readYaml(gp, "starts", &c.models.gp.starts);
    readYaml(gp, "max_exact_pairs", &c.models.gp.max_exact_pairs);
    readYaml(gp, "inducing_points", &c.models.gp.inducing_points);
    readYaml(gp, "outlier_threshold", &c.models.gp.outlier_threshold);
    validate(c.models.gp);

    where = source;
    if (c.prior_model != "none" && c.prior_model != "diff_drive" && c.prior_model != "tricycle" &&
        c.prior_model != "mecanum" && c.prior_model != "skid_steer") {
      throw std::runtime_error(
          "prior_model must be 'none', 'diff_drive', 'tricycle', 'mecanum' or 'skid_steer', got '" +
          c.prior_model + "'");
    }
    requireKnownModel(c.model, "model");
    for (const std::string& name : c.compare_models)
      requireKnownModel(name, "compare_models");
  } catch (...) {
    rethrowWithYamlContext(source, where);
  }
  return c;
}

CalibrationConfig loadCalibrationConfig(const std::string& path)
{
  return parseCalibrationConfig(readTextFile(path, "the configuration"), path);
}

std::vector<EncoderChannelOptions> encoderChannels(const CalibrationConfig& config)
{
  std::vector<EncoderChannelOptions> channels;
  for (const JointConfig& joint : config.joints) {
    const bool incremental = joint.kind == EncoderKind::kIncremental;
    channels.push_back(
        {joint.name, joint.kind,
         incremental && joint.counter_bits > 0 ? std::ldexp(1.0, joint.counter_bits) : 0.0,
         incremental ? 0.0 : joint.units_per_turn, joint.max_turns_per_s * joint.units_per_turn});
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
