// The shipped configurations parse to the values they parsed to before the configuration schema
// (calibration_config_schema.h): every field of CalibrationConfig, printed with 17 digits, is
// compared with test/config/data/shipped_configs.txt, written by the parser before the schema
// (commit 0257d0b); and the effective configuration (--print-config) reads back to the same values.
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/config/calibration_config_schema.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kRoot = kConfig + "/..";

/// Appends "name = value" lines, doubles with 17 significant digits.
class Fingerprint
{
public:
  void add(const std::string& name, double value)
  {
    char text[64];
    std::snprintf(text, sizeof(text), "%.17g", value);
    lines_ << name << " = " << text << "\n";
  }
  void add(const std::string& name, const std::string& value)
  {
    lines_ << name << " = '" << value << "'\n";
  }
  void add(const std::string& name, const std::vector<std::string>& values)
  {
    for (std::size_t i = 0; i < values.size(); ++i)
      add(name + "[" + std::to_string(i) + "]", values[i]);
    add(name + ".size", static_cast<double>(values.size()));
  }
  void add(const std::string& name, const std::vector<double>& values)
  {
    for (std::size_t i = 0; i < values.size(); ++i)
      add(name + "[" + std::to_string(i) + "]", values[i]);
    add(name + ".size", static_cast<double>(values.size()));
  }
  void add(const std::string& name, const Pose2& pose)
  {
    add(name + ".x", pose.x());
    add(name + ".y", pose.y());
    add(name + ".theta", pose.theta());
  }
  std::string text() const { return lines_.str(); }

private:
  std::ostringstream lines_;
};

#define FIELD(f, expression) f.add(#expression, expression)
#define NUMBER(f, expression) f.add(#expression, static_cast<double>(expression))

void addJoints(const CalibrationConfig& c, Fingerprint& f)
{
  for (const JointConfig& joint : c.joints) {
    FIELD(f, joint.name);
    NUMBER(f, joint.kind);
    FIELD(f, joint.units_per_turn);
    NUMBER(f, joint.counter_bits);
    FIELD(f, joint.max_turns_per_s);
    FIELD(f, joint.sign);
  }
  FIELD(f, c.joint_state_topic);
  NUMBER(f, c.ego_motion);
  FIELD(f, c.scan_topic);
  FIELD(f, c.ego_motion_topic);
  FIELD(f, c.ego_motion_sigma_m);
  FIELD(f, c.ego_motion_sigma_rad);
  NUMBER(f, c.cloud.scan_from);
  FIELD(f, c.cloud.band_min_m);
  FIELD(f, c.cloud.band_max_m);
  FIELD(f, c.cloud.roll_rad);
  FIELD(f, c.cloud.pitch_rad);
  FIELD(f, c.cloud.voxel_size_m);
  NUMBER(f, c.cloud.outlier_neighbours);
  FIELD(f, c.cloud.outlier_stddev);
  FIELD(f, c.cloud.angular_resolution_rad);
  FIELD(f, c.cloud.range_min_m);
  FIELD(f, c.cloud.range_max_m);
  NUMBER(f, c.cloud.min_points);
  FIELD(f, c.cloud.point_times.field);
  NUMBER(f, c.cloud.point_times.unit);
  NUMBER(f, c.cloud.point_times.reference);
  FIELD(f, c.cloud.point_times.limit_s);
}

void addCollector(const CalibrationConfig& c, Fingerprint& f)
{
  const CollectorOptions& k = c.collector;
  FIELD(f, k.keyframe_interval_s);
  FIELD(f, k.min_translation_m);
  FIELD(f, k.min_rotation_rad);
  NUMBER(f, k.compensate_sweep);
  FIELD(f, k.time_offset_s);
  FIELD(f, k.max_encoder_gap_s);
  NUMBER(f, k.check_consistency);
  FIELD(f, k.consistency_translation_m);
  FIELD(f, k.consistency_rotation_rad);
  NUMBER(f, k.pair_motion_from_chain);
  FIELD(f, k.plicp.max_correspondence_distance_m);
  NUMBER(f, k.plicp.max_iterations);
  FIELD(f, k.plicp.range_sigma_m);
  FIELD(f, k.plicp.max_correction_translation_m);
  FIELD(f, k.plicp.max_correction_rotation_rad);
  NUMBER(f, k.plicp.min_points);
  FIELD(f, k.plicp.trim_keep_fraction);
  NUMBER(f, k.plicp.line_fit.segment_fallback_max_surface_points);
  FIELD(f, k.plicp.line_fit.veiling_min_angle_rad);
  NUMBER(f, c.estimate_time_offset);
  FIELD(f, c.time_offset_search_min_s);
  FIELD(f, c.time_offset_search_max_s);
  FIELD(f, c.fit_intervals_s);
  FIELD(f, c.model);
  FIELD(f, c.compare_models);
  FIELD(f, c.prior_model);
  FIELD(f, c.output_directory);
}

void addWheeledModels(const ModelFactoryOptions& m, Fingerprint& f)
{
  FIELD(f, m.joints.names);
  for (EncoderKind kind : m.joints.kinds)
    NUMBER(f, kind);
  NUMBER(f, m.diff_drive.layout.left_index);
  NUMBER(f, m.diff_drive.layout.right_index);
  FIELD(f, m.diff_drive.layout.ticks_per_turn);
  FIELD(f, m.diff_drive.initial_left_radius_m);
  FIELD(f, m.diff_drive.initial_right_radius_m);
  FIELD(f, m.diff_drive.initial_separation_m);
  FIELD(f, m.diff_drive.initial_T_base_sensor);
  FIELD(f, m.diff_drive.huber_threshold);
  NUMBER(f, m.diff_drive.max_iterations);
  NUMBER(f, m.diff_drive.yaw_starts);
  for (std::size_t i = 0; i < 4; ++i)
    FIELD(f, m.mecanum.initial_radius_m[i]);
  NUMBER(f, m.mecanum.layout.front_left_index);
  NUMBER(f, m.mecanum.layout.front_right_index);
  NUMBER(f, m.mecanum.layout.rear_left_index);
  NUMBER(f, m.mecanum.layout.rear_right_index);
  FIELD(f, m.mecanum.layout.ticks_per_turn);
  FIELD(f, m.mecanum.initial_lx_plus_ly_m);
  FIELD(f, m.mecanum.initial_T_base_sensor);
  FIELD(f, m.mecanum.huber_threshold);
  NUMBER(f, m.mecanum.max_iterations);
  NUMBER(f, m.mecanum.yaw_starts);
  for (int index : m.skid_steer.left_indices)
    NUMBER(f, index);
  for (int index : m.skid_steer.right_indices)
    NUMBER(f, index);
  FIELD(f, m.skid_steer.ticks_per_turn);
  FIELD(f, m.skid_steer.wheel_radius_m);
  FIELD(f, m.skid_steer.wheel_separation_m);
  FIELD(f, m.skid_steer.initial_T_base_sensor);
  FIELD(f, m.skid_steer.huber_threshold);
  NUMBER(f, m.skid_steer.max_iterations);
  NUMBER(f, m.skid_steer.yaw_starts);
}

void addOtherModels(const ModelFactoryOptions& m, Fingerprint& f)
{
  NUMBER(f, m.tricycle.layout.steering_index);
  NUMBER(f, m.tricycle.layout.traction_index);
  FIELD(f, m.tricycle.layout.steering_ticks_per_turn);
  FIELD(f, m.tricycle.layout.traction_ticks_per_turn);
  FIELD(f, m.tricycle.initial.steering_scale);
  FIELD(f, m.tricycle.initial.traction_scale_m_per_turn);
  FIELD(f, m.tricycle.initial.axis_length_m);
  FIELD(f, m.tricycle.initial.steering_offset_rad);
  FIELD(f, m.tricycle.initial.T_base_sensor);
  FIELD(f, m.tricycle.calibration.translation_sigma_m);
  FIELD(f, m.tricycle.calibration.rotation_sigma_rad);
  FIELD(f, m.tricycle.calibration.huber_threshold);
  NUMBER(f, m.tricycle.calibration.max_iterations);
  NUMBER(f, m.tricycle.calibration.yaw_starts);
  FIELD(f, m.linear.huber_threshold);
  FIELD(f, m.linear.outlier_threshold);
  NUMBER(f, m.linear.max_iterations);
  NUMBER(f, m.gp.kernel);
  NUMBER(f, m.gp.mean);
  NUMBER(f, m.gp.starts);
  NUMBER(f, m.gp.max_exact_pairs);
  NUMBER(f, m.gp.inducing_points);
  FIELD(f, m.gp.outlier_threshold);
}

/// Every field the configuration sets, one "name = value" line each.
std::string fingerprint(const CalibrationConfig& config)
{
  Fingerprint f;
  addJoints(config, f);
  addCollector(config, f);
  addWheeledModels(config.models, f);
  addOtherModels(config.models, f);
  return f.text();
}

/// The calibration configurations shipped or used by the rostests (config/node.yaml holds the
/// node's ROS parameters, config/sim/ scenarios and worlds: not calibration configurations).
const std::vector<std::string> kShipped = {"config/diff_drive.yaml",
                                           "config/diff_drive_demo.yaml",
                                           "config/diff_drive_lidar3d.yaml",
                                           "config/mecanum.yaml",
                                           "config/mines.yaml",
                                           "config/skid_steer.yaml",
                                           "config/tricycle.yaml",
                                           "test/live_node/config/tricycle_tracker.yaml"};

std::string allFingerprints()
{
  std::string text;
  for (const std::string& path : kShipped) {
    text += "### " + path + "\n" + fingerprint(loadCalibrationConfig(kRoot + "/" + path));
    // Each model the node may be asked for, as ~calibrate resolves it.
    for (const char* model : {"diff_drive", "linear", "gp"}) {
      std::ifstream file(kRoot + "/" + path);
      std::stringstream config_text;
      config_text << file.rdbuf();
      try {
        text += "## " + std::string(model) + "\n" +
                fingerprint(configForModel(config_text.str(), model, "", path));
      } catch (const std::runtime_error&) {
        text += "## " + std::string(model) + ": refused\n";
      }
    }
  }
  return text;
}

TEST(ShippedConfigurations, ParseToTheValuesOfTheParserBeforeTheSchema)
{
  const std::string expected_path = kRoot + "/test/config/data/shipped_configs.txt";
  const std::string actual = allFingerprints();
  if (std::getenv("ODOMETRY_CALIBRATION_WRITE_EXPECTED") != nullptr)
    std::ofstream(expected_path) << actual;
  std::ifstream file(expected_path);
  ASSERT_TRUE(file.good()) << expected_path;
  std::stringstream expected;
  expected << file.rdbuf();
  EXPECT_EQ(actual, expected.str());
}

TEST(ShippedConfigurations, TheirEffectiveConfigurationReadsBackToTheSameValues)
{
  for (const std::string& path : kShipped) {
    const CalibrationConfig config = loadCalibrationConfig(kRoot + "/" + path);
    const std::string effective = formatEffectiveConfig(config);
    EXPECT_EQ(fingerprint(parseCalibrationConfig(effective, path + " (effective)")),
              fingerprint(config))
        << effective;
  }
}

}  // namespace
}  // namespace odometry_calibration
