// The configuration schema (calibration_config_schema.h): malformed configurations refused with
// the full key, the value and what is allowed; the per-call options checked the same way; the
// effective configuration printed and read back; the README's table generated from it.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/config/calibration_config_schema.h"

namespace odometry_calibration {
namespace {

const std::string kJoints =
    "joints: [{name: l, units_per_turn: 100}, {name: r, units_per_turn: 100}]\n";
const std::string kTricycleJoints =
    "joints: [{name: s, kind: absolute, units_per_turn: 8192}, {name: t}]\nmodel: tricycle\n";

/// A malformed configuration and what its refusal must name.
struct Malformed
{
  std::string text;   ///< the whole configuration
  std::string key;    ///< the full key the message names
  std::string value;  ///< the value it names (or the cause, for a missing value)
  std::string also;   ///< a further part of the message ("" for none)
};

std::string refusal(const std::string& text)
{
  try {
    parseCalibrationConfig(text, "c.yaml");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

/// Keyframes: positive, at least a fast sensor's period, bounded.
const std::vector<Malformed> kKeyframeCases = {
    {kJoints + "keyframes: {interval_s: -0.5}\n", "keyframes.interval_s", "-0.5",
     "allowed: a number in [0.01, 60] s"},
    {kJoints + "keyframes: {interval_s: 1e-300}\n", "keyframes.interval_s", "1e-300", "[0.01, 60]"},
    {kJoints + "keyframes: {interval_s: 0}\n", "keyframes.interval_s", "0", "[0.01, 60]"},
    {kJoints + "keyframes: {interval_s: .nan}\n", "keyframes.interval_s", ".nan", "finite"},
    {kJoints + "keyframes: {interval_s: .inf}\n", "keyframes.interval_s", ".inf", "finite"},
    {kJoints + "keyframes: {interval_s: 3600}\n", "keyframes.interval_s", "3600", "[0.01, 60]"},
    {kJoints + "keyframes: {interval_s: fast}\n", "keyframes.interval_s", "fast", "not a number"},
    {kJoints + "keyframes: {interval_s: }\n", "keyframes.interval_s", "(no value)", "allowed"},
    {kJoints + "keyframes: {time_offset_s: 10}\n", "keyframes.time_offset_s", "10", "(-5, 5) s"},
    {kJoints + "keyframes: {time_offset_search_s: [0.4, -0.4]}\n", "keyframes.time_offset_search_s",
     "[0.4, -0.4]", "increasing"},
    {kJoints + "keyframes: {time_offset_search_s: [-0.4]}\n", "keyframes.time_offset_search_s",
     "[-0.4]", "a list of 2"},
    {kJoints + "keyframes: {fit_intervals_s: [0.001, 0.5]}\n", "keyframes.fit_intervals_s[0]",
     "0.001", "[0.01, 60] s"},
    {kJoints + "keyframes: {fit_intervals_s: [0.5, 0.3]}\n", "keyframes.fit_intervals_s",
     "[0.5, 0.3]", "must increase"},
    {kJoints + "keyframes: {max_encoder_gap_s: -0.25}\n", "keyframes.max_encoder_gap_s", "-0.25",
     "[0, 60] s"},
    {kJoints + "keyframes: {consistency_translation_m: -0.03}\n",
     "keyframes.consistency_translation_m", "-0.03", "[1e-04, 10] m"},
    {kJoints + "keyframes: {consistency_rotation_rad: 0}\n", "keyframes.consistency_rotation_rad",
     "0", "rad"},
    {kJoints + "keyframes: {min_translation_m: -1}\n", "keyframes.min_translation_m", "-1",
     "[0, 100] m"},
    {kJoints + "keyframes: {check_consistency: maybe}\n", "keyframes.check_consistency", "maybe",
     "true or false"},
    {kJoints + "keyframes: 0.5\n", "keyframes", "expected a map", ""},
    {kJoints + "keyframes: {interval: 0.5}\n", "keyframes", "unknown key 'interval'", "interval_s"},
};

/// The differential drive: positive lengths, bounded counts.
const std::vector<Malformed> kDiffDriveCases = {
    {kJoints + "diff_drive: {wheel_separation_m: -0.33}\n", "diff_drive.wheel_separation_m",
     "-0.33", "[0.01, 50] m"},
    {kJoints + "diff_drive: {wheel_radius_m: 1e308}\n", "diff_drive.wheel_radius_m", "1e308",
     "[0.001, 5] m"},
    {kJoints + "diff_drive: {wheel_radius_m: 0}\n", "diff_drive.wheel_radius_m", "0",
     "[0.001, 5] m"},
    {kJoints + "diff_drive: {wheel_radius_m: 1e-300}\n", "diff_drive.wheel_radius_m", "1e-300",
     "[0.001, 5] m"},
    {kJoints + "diff_drive: {wheel_separation_m: 1e-300}\n", "diff_drive.wheel_separation_m",
     "1e-300", "[0.01, 50] m"},
    {kJoints + "diff_drive: {wheel_separation_m: -.inf}\n", "diff_drive.wheel_separation_m",
     "-.inf", "[0.01, 50] m"},
    {kJoints + "diff_drive: {sensor_pose: [0, 1e-300, 1e308]}\n", "diff_drive.sensor_pose[2]",
     "1e308", "[-100, 100]"},
    {kJoints + "diff_drive: {wheel_radius_m: 0.05m}\n", "diff_drive.wheel_radius_m", "0.05m",
     "not a number"},
    {kJoints + "diff_drive: {huber_threshold: -1}\n", "diff_drive.huber_threshold", "-1",
     "[0.01, 100] sigma"},
    {kJoints + "diff_drive: {huber_threshold: 1e-300}\n", "diff_drive.huber_threshold", "1e-300",
     "[0.01, 100] sigma"},
    {kJoints + "diff_drive: {max_iterations: 0}\n", "diff_drive.max_iterations", "0", "[1, 10000]"},
    {kJoints + "diff_drive: {max_iterations: 2000000000}\n", "diff_drive.max_iterations",
     "2000000000", "[1, 10000]"},
    {kJoints + "diff_drive: {yaw_starts: 361}\n", "diff_drive.yaw_starts", "361", "[1, 360]"},
    {kJoints + "diff_drive: {yaw_starts: 2.5}\n", "diff_drive.yaw_starts", "2.5", "not an integer"},
    {kJoints + "diff_drive: {sensor_pose: [0, 0]}\n", "diff_drive.sensor_pose", "[0, 0]",
     "a list of 3"},
    {kJoints + "diff_drive: {sensor_pose: [0, 0, .nan]}\n", "diff_drive.sensor_pose[2]", ".nan",
     "finite"},
    {kJoints + "diff_drive: {sensor_pose: [1e9, 0, 0]}\n", "diff_drive.sensor_pose[0]", "1e9",
     "[-100, 100]"},
    {kJoints + "diff_drive: {left_joint: front}\n", "diff_drive.left_joint", "front", "joints"},
};

/// The Gaussian process: counts that bound memory and time.
const std::vector<Malformed> kGpCases = {
    {kJoints + "gp: {starts: 2000000000}\n", "gp.starts", "2000000000", "[1, 64]"},
    {kJoints + "gp: {starts: 0}\n", "gp.starts", "0", "[1, 64]"},
    {kJoints + "gp: {starts: 99999999999999999999}\n", "gp.starts", "99999999999999999999",
     "[1, 64]"},
    {kJoints + "gp: {inducing_points: 1000000}\n", "gp.inducing_points", "1000000", "[1, 2000]"},
    {kJoints + "gp: {max_exact_pairs: 1e9}\n", "gp.max_exact_pairs", "1e9", "not an integer"},
    {kJoints + "gp: {max_exact_pairs: -5}\n", "gp.max_exact_pairs", "-5", "[1, 10000]"},
    {kJoints + "gp: {outlier_threshold: -1}\n", "gp.outlier_threshold", "-1", "[0, 1000]"},
    {kJoints + "gp: {kernel: cubic}\n", "gp.kernel", "cubic", "rbf, linear, rbf+linear"},
    {kJoints + "gp: {mean: quadratic}\n", "gp.mean", "quadratic", "linear, zero"},
    {kJoints + "linear: {huber_threshold: -1.345}\n", "linear.huber_threshold", "-1.345",
     "[0.01, 100]"},
    {kJoints + "linear: {huber_threshold: 6, outlier_threshold: 5}\n", "linear.outlier_threshold",
     "5", "linear.huber_threshold (6)"},
};

/// Duplicated keys: YAML would keep one silently.
const std::vector<Malformed> kDuplicateKeyCases = {
    {kJoints + "model: diff_drive\nmodel: gp\n", "model", "appears twice", ""},
    {kJoints + "keyframes: {interval_s: 0.5, interval_s: 0.3}\n", "keyframes.interval_s",
     "appears twice", ""},
    {"joints: [{name: l, name: r}, {name: x}]\n", "joints[0].name", "appears twice", ""},
    {kJoints + "gp: {starts: 4}\ngp: {starts: 8}\n", "gp", "appears twice", ""},
};

/// Joints.
const std::vector<Malformed> kJointsCases = {
    {"joints: [{name: l, units_per_turn: -100}, {name: r}]\n", "joints[0].units_per_turn", "-100",
     "in [0.001, 1000000000] units/turn"},
    {"joints: [{name: l, units_per_turn: 1e308}, {name: r}]\n", "joints[0].units_per_turn", "1e308",
     "[0.001, 1000000000]"},
    {"joints: [{name: l, units_per_turn: 1e-300}, {name: r}]\n", "joints[0].units_per_turn",
     "1e-300", "[0.001, 1000000000] units/turn"},
    {"joints: [{name: l, units_per_turn: .inf}, {name: r}]\n", "joints[0].units_per_turn", ".inf",
     "[0.001, 1000000000]"},
    {"joints: [{name: l, units_per_turn: .nan}, {name: r}]\n", "joints[0].units_per_turn", ".nan",
     "[0.001, 1000000000]"},
    {"joints: [{name: l, counter_bits: 64}, {name: r}]\n", "joints[0].counter_bits", "64",
     "[0, 52]"},
    {"joints: [{name: l}, {name: r, sign: 0.5}]\n", "joints[1].sign", "0.5", "1 or -1"},
    {"joints: [{name: l, max_turns_per_s: -1}, {name: r}]\n", "joints[0].max_turns_per_s", "-1",
     "[0, 10000] turns/s"},
    {"joints: [{name: l, kind: sideways}, {name: r}]\n", "joints[0].kind", "sideways",
     "incremental, absolute"},
    {"joints: [{kind: incremental}, {name: r}]\n", "joints[0].name", "required", ""},
    {"joints: [{name: l}, {name: l}]\n", "joints[1].name", "'l'", "joints[0]"},
    {"joints: []\n", "joints", "required", ""},
    {"joints: [{name: l, wheel: 1}, {name: r}]\n", "joints[0]", "unknown key 'wheel'", ""},
    {"model: linear\n", "joints", "required", ""},
};

/// Scan matching.
const std::vector<Malformed> kScanMatchingCases = {
    {kJoints + "scan_matching: {max_iterations: 2000000000}\n", "scan_matching.max_iterations",
     "2000000000", "[1, 1000]"},
    {kJoints + "scan_matching: {min_points: 2}\n", "scan_matching.min_points", "2", "[3, 100000]"},
    {kJoints + "scan_matching: {trim_keep_fraction: 0}\n", "scan_matching.trim_keep_fraction", "0",
     "[0.01, 1]"},
    {kJoints + "scan_matching: {veiling_min_angle_rad: 1.5708}\n",
     "scan_matching.veiling_min_angle_rad", "1.5708", "rad"},
    {kJoints + "scan_matching: {max_correspondence_distance_m: -0.5}\n",
     "scan_matching.max_correspondence_distance_m", "-0.5", "[0.001, 10] m"},
    {kJoints + "scan_matching: {max_correction_translation_m: 1e-300}\n",
     "scan_matching.max_correction_translation_m", "1e-300", "[1e-04, 100] m"},
    {kJoints + "scan_matching: {max_correction_translation_m: 1e308}\n",
     "scan_matching.max_correction_translation_m", "1e308", "[1e-04, 100] m"},
    {kJoints + "scan_matching: {range_sigma_m: 0}\n", "scan_matching.range_sigma_m", "0",
     "[1e-05, 1] m"},
    {kJoints + "scan_matching: {max_correction_rotation_rad: 10}\n",
     "scan_matching.max_correction_rotation_rad", "10", "rad"},
    {kJoints + "scan_matching: {segment_fallback_max_surface_points: -1}\n",
     "scan_matching.segment_fallback_max_surface_points", "-1", "[0, 100000]"},
};

/// The ego-motion source and the cloud.
const std::vector<Malformed> kEgoMotionCases = {
    {kJoints + "ego_motion: {source: sonar}\n", "ego_motion.source", "sonar", "scan, cloud"},
    {kJoints + "ego_motion: {source: pose}\n", "ego_motion.topic", "pose", "needs 'topic'"},
    {kJoints + "ego_motion: {sigma_m: -0.005}\n", "ego_motion.sigma_m", "-0.005", "[1e-06, 1] m"},
    {kJoints + "ego_motion: {source: cloud, topic: /p, cloud: {band_m: [1, 0]}}\n",
     "ego_motion.cloud.band_m", "[1, 0]", "band_min_m < band_max_m"},
    {kJoints + "ego_motion: {cloud: {voxel_size_m: -1}}\n", "ego_motion.cloud.voxel_size_m", "-1",
     "[0, 10] m"},
    {kJoints + "ego_motion: {cloud: {range_min_m: 50, range_max_m: 40}}\n",
     "ego_motion.cloud.range_max_m", "40", "range_min_m (50)"},
    {kJoints + "ego_motion: {cloud: {angular_resolution_rad: 0}}\n",
     "ego_motion.cloud.angular_resolution_rad", "0", "(1e-05, 0.1] rad"},
    {kJoints + "ego_motion: {cloud: {point_time_unit: fortnights}}\n",
     "ego_motion.cloud.point_time_unit", "fortnights", "auto, s, ms, us, ns"},
    {kJoints + "ego_motion: {cloud: {roll_rad: 2}}\n", "ego_motion.cloud.roll_rad", "2", "rad"},
    {kJoints + "ego_motion: {cloud: {outlier_neighbours: -3}}\n",
     "ego_motion.cloud.outlier_neighbours", "-3", "[0, 1000]"},
    {kJoints + "ego_motion: {cloud: {band: 1}}\n", "ego_motion.cloud", "unknown key 'band'", ""},
};

/// The other models' start values and options.
const std::vector<Malformed> kOtherModelCases = {
    {"joints: [{name: s}, {name: t}]\nmodel: tricycle\n", "tricycle.steering_joint", "'s'",
     "must be kind: absolute"},
    {"joints: [{name: s, kind: absolute}, {name: t, kind: absolute}]\nmodel: tricycle\n",
     "tricycle.traction_joint", "'t'", "traction joint incremental"},
    {kTricycleJoints + "tricycle: {axis_length_m: -1.5}\n", "tricycle.axis_length_m", "-1.5",
     "[0.01, 50] m"},
    {kTricycleJoints + "tricycle: {axis_length_m: 1e308}\n", "tricycle.axis_length_m", "1e308",
     "[0.01, 50] m"},
    {kTricycleJoints + "tricycle: {steering_scale: 0}\n", "tricycle.steering_scale", "0",
     "[1e-04, 100]"},
    {kTricycleJoints + "tricycle: {traction_scale_m_per_turn: 1e-300}\n",
     "tricycle.traction_scale_m_per_turn", "1e-300", "[1e-06, 100] m/turn"},
    {kTricycleJoints + "tricycle: {huber_threshold: -3}\n", "tricycle.huber_threshold", "-3",
     "[0, 100]"},
    {kTricycleJoints + "tricycle: {translation_sigma_m: 0}\n", "tricycle.translation_sigma_m", "0",
     "[1e-06, 10] m"},
    {kJoints + "mecanum: {wheel_radii_m: [0.05, 0.05, -0.05, 0.05]}\n", "mecanum.wheel_radii_m[2]",
     "-0.05", "[0.001, 5] m"},
    {kJoints + "mecanum: {lx_plus_ly_m: 0}\n", "mecanum.lx_plus_ly_m", "0", "[0.01, 50] m"},
    {kJoints + "skid_steer: {wheel_separation_m: -0.5}\n", "skid_steer.wheel_separation_m", "-0.5",
     "[0.01, 50] m"},
    {kJoints + "skid_steer: {wheel_radius_m: 1e-300}\n", "skid_steer.wheel_radius_m", "1e-300",
     "[0.001, 5] m"},
    {kJoints + "skid_steer: {left_joints: []}\n", "skid_steer.left_joints", "[]", "a list of 1"},
};

/// The top-level keys.
const std::vector<Malformed> kTopLevelCases = {
    {kJoints + "prior_model: magic\n", "prior_model", "magic", "none, diff_drive"},
    {kJoints + "model: magic\n", "model", "magic", "linear, diff_drive, gp"},
    {kJoints + "compare_models: [linear, gpp]\n", "compare_models[1]", "gpp", "one of"},
    {kJoints + "output_directory: \"\"\n", "output_directory", "\"\"", "non-empty"},
    {kJoints + "joint_state_topic: [a, b]\n", "joint_state_topic", "[a, b]", "not a string"},
};

std::vector<Malformed> malformedConfigurations()
{
  std::vector<Malformed> all;
  for (const auto* cases :
       {&kKeyframeCases, &kDiffDriveCases, &kGpCases, &kDuplicateKeyCases, &kJointsCases,
        &kScanMatchingCases, &kEgoMotionCases, &kOtherModelCases, &kTopLevelCases})
    all.insert(all.end(), cases->begin(), cases->end());
  return all;
}

TEST(CalibrationConfigSchema, RefusesEachMalformedConfigurationNamingKeyAndValue)
{
  const std::vector<Malformed> cases = malformedConfigurations();
  EXPECT_GE(cases.size(), 60u);
  for (const Malformed& c : cases) {
    const std::string message = refusal(c.text);
    ASSERT_FALSE(message.empty()) << "accepted:\n" << c.text;
    EXPECT_EQ(message.rfind("c.yaml: " + c.key, 0), 0u) << message;
    EXPECT_NE(message.find(c.value), std::string::npos) << message;
    EXPECT_NE(message.find(c.also), std::string::npos) << message;
  }
}

TEST(CalibrationConfigSchema, HugeStartCountsAreRefusedBeforeAnyWork)
{
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(refusal(kJoints + "gp: {starts: 2000000000}\n").find("gp.starts"), std::string::npos);
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(elapsed_s, 0.5);
}

TEST(CalibrationConfigSchema, PerCallOptionsAreCheckedByTheSameSchema)
{
  auto refused = [](const std::string& model, const std::string& options) -> std::string {
    try {
      if (model.empty())
        overrideModelOptions(kJoints, options, "c.yaml");
      else
        configForModel(kJoints, model, options, "c.yaml");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  const std::string radius = refused("diff_drive", "{diff_drive: {wheel_radius_m: 1e308}}");
  EXPECT_NE(radius.find("diff_drive.wheel_radius_m: 1e308 is out of range"), std::string::npos)
      << radius;
  EXPECT_NE(radius.find("[0.001, 5] m"), std::string::npos) << radius;
  EXPECT_NE(refused("", "{gp: {starts: 2000000000}}").find("gp.starts"), std::string::npos);
  EXPECT_NE(refused("gp", "{gp: {kernel: rbf, kernel: linear}}").find("gp.kernel"),
            std::string::npos);
  EXPECT_NE(refused("", "{gp: {kernel: rbf}, gp: {starts: 2}}").find("appears twice"),
            std::string::npos);
  EXPECT_NE(refused("", "{linear: {huber_threshold: -1}}").find("linear.huber_threshold"),
            std::string::npos);
  EXPECT_NE(refused("", "{keyframes: {interval_s: 0.3}}").find("cannot be changed per call"),
            std::string::npos);
  EXPECT_EQ(refused("gp", "{gp: {starts: 8}}"), "");
  EXPECT_EQ(configForModel(kJoints, "gp", "{gp: {starts: 8}}", "c.yaml").models.gp.starts, 8);
}

TEST(CalibrationConfigSchema, EveryKeyIsDeclaredOnceWithADescriptionAndAValidDefault)
{
  std::set<std::string> keys;
  for (const ConfigKeySpec* spec : calibrationConfigSpecs()) {
    EXPECT_TRUE(keys.insert(spec->key).second) << spec->key << " declared twice";
    EXPECT_FALSE(spec->description.empty()) << spec->key;
    EXPECT_FALSE(formatConfigDefault(*spec).empty()) << spec->key;
    if (spec->default_value && spec->type == ConfigType::kDouble) {
      EXPECT_TRUE(spec->range.contains(std::get<double>(*spec->default_value))) << spec->key;
    }
    if (spec->default_value && spec->type == ConfigType::kInt) {
      const double value = static_cast<double>(std::get<long long>(*spec->default_value));
      EXPECT_TRUE(spec->range.contains(value)) << spec->key;
    }
  }
  EXPECT_GT(keys.size(), 90u);
}

TEST(CalibrationConfigSchema, TheEffectiveConfigurationReadsBackAndCommentsEveryKey)
{
  const CalibrationConfig config = parseCalibrationConfig(
      kJoints +
          "keyframes: {interval_s: 0.3, fit_intervals_s: [0.3, 0.6]}\ngp: {starts: 6}\n"
          "ego_motion: {source: cloud, topic: /points, cloud: {point_time_field: \"\"}}\n",
      "c.yaml");
  const std::string text = formatEffectiveConfig(config);
  EXPECT_NE(text.find("  interval_s: 0.3"), std::string::npos) << text;
  EXPECT_NE(text.find("keyframe spacing T"), std::string::npos) << text;
  EXPECT_NE(text.find("[0.01, 60] s"), std::string::npos) << text;
  EXPECT_NE(text.find("  starts: 6"), std::string::npos) << text;
  const CalibrationConfig again = parseCalibrationConfig(text, "effective.yaml");
  EXPECT_EQ(formatEffectiveConfig(again), text);
  EXPECT_EQ(again.collector.keyframe_interval_s, 0.3);
  EXPECT_EQ(again.fit_intervals_s, config.fit_intervals_s);
  EXPECT_EQ(again.ego_motion, EgoMotionSource::kCloud);
  for (const ConfigKeySpec* spec : calibrationConfigSpecs()) {
    const std::string name = spec->key.substr(spec->key.find_last_of(".") + 1);
    EXPECT_NE(text.find(name + ": "), std::string::npos) << spec->key;
  }
}

TEST(CalibrationConfigSchema, TheEffectiveConfigurationReadsBackItsSources)
{
  const CalibrationConfig config = parseCalibrationConfig(
      kJoints +
          "ego_motion:\n  sources:\n    - {topic: /scan_front, frame: laser_front}\n"
          "    - {topic: /scan_rear, frame: laser_rear, time_offset_s: 0.05}\n",
      "c.yaml");
  const std::string text = formatEffectiveConfig(config);
  EXPECT_NE(text.find("# scan_topic: (replaced by ego_motion.sources)"), std::string::npos) << text;
  const CalibrationConfig again = parseCalibrationConfig(text, "effective.yaml");
  EXPECT_EQ(formatEffectiveConfig(again), text);
  ASSERT_EQ(again.ego_motion_sources.size(), 2u);
  EXPECT_EQ(again.ego_motion_sources[1].frame, "laser_rear");
  EXPECT_DOUBLE_EQ(again.ego_motion_sources[1].time_offset_s, 0.05);
  EXPECT_TRUE(std::isnan(again.ego_motion_sources[0].time_offset_s));
}

/// Joints every model can use: diff_drive (the first two), mecanum (the first four), skid_steer
/// (*left* / *right*), tricycle (steer, left_front); all fitted or compared.
const std::string kEveryModel =
    "joints: [{name: left_front}, {name: right_front}, {name: left_rear}, {name: right_rear},\n"
    "         {name: steer, kind: absolute}]\n"
    "compare_models: [tricycle, mecanum, skid_steer, linear, gp]\n"
    "tricycle: {steering_joint: steer, traction_joint: left_front}\n";

/// `base` with `key` (dotted) set to `value`.
std::string withValue(const std::string& base, const std::string& key, const std::string& value)
{
  YAML::Node root = YAML::Load(base);
  YAML::Node node = root;
  std::istringstream parts(key);
  std::vector<std::string> names;
  for (std::string part; std::getline(parts, part, '.');)
    names.push_back(part);
  for (std::size_t i = 0; i + 1 < names.size(); ++i) {
    if (!node[names[i]])
      node[names[i]] = YAML::Node(YAML::NodeType::Map);
    node.reset(node[names[i]]);
  }
  node[names.back()] = YAML::Load(value);
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

/// The smallest and largest value `spec` allows.
std::vector<double> rangeEnds(const ConfigKeySpec& spec)
{
  const double low = spec.range.min_open ? std::nextafter(spec.range.min, 1e300) : spec.range.min;
  const double high = spec.range.max_open ? std::nextafter(spec.range.max, -1e300) : spec.range.max;
  if (spec.type == ConfigType::kInt)
    return {std::ceil(low), std::floor(high)};
  return {low, high};
}

// Every value the schema allows passes the option structs' own checks too (so that a refusal
// always comes from the schema, naming the full key): each number at both ends of its range.
TEST(CalibrationConfigSchema, EveryNumberTheSchemaAllowsIsAccepted)
{
  // Checks across keys: a partner set so that both ends of the key are consistent with it.
  const std::map<std::string, std::pair<std::string, std::string>> partners = {
      {"linear.huber_threshold", {"linear.outlier_threshold", "1000"}},
      {"linear.outlier_threshold", {"linear.huber_threshold", "0.5"}},
      {"ego_motion.cloud.range_min_m", {"ego_motion.cloud.range_max_m", "1000"}},
      {"ego_motion.cloud.range_max_m", {"ego_motion.cloud.range_min_m", "0"}}};
  std::size_t tried = 0;
  for (const auto& entry : calibrationConfigSchema()) {
    const ConfigKeySpec& spec = entry.spec;
    if (spec.type != ConfigType::kDouble && spec.type != ConfigType::kInt)
      continue;
    for (double end : rangeEnds(spec)) {
      const std::string value = spec.type == ConfigType::kInt
                                    ? formatConfigValue(static_cast<long long>(end))
                                    : formatConfigValue(end);
      std::string text = withValue(kEveryModel, spec.key, value);
      const auto partner = partners.find(spec.key);
      if (partner != partners.end())
        text = withValue(text, partner->second.first, partner->second.second);
      EXPECT_EQ(refusal(text), "") << spec.key << ": " << value;
      ++tried;
    }
  }
  EXPECT_GT(tried, 100u);
}

const std::string kTableBegin = "<!-- configuration table: generated from the schema -->\n";
const std::string kTableEnd = "<!-- end of the generated configuration table -->";

/// The README's text between the two markers of the generated table.
std::string readmeTable(const std::string& readme)
{
  const std::size_t from = readme.find(kTableBegin);
  const std::size_t to = readme.find(kTableEnd);
  if (from == std::string::npos || to == std::string::npos || to < from)
    return "(markers missing)";
  return readme.substr(from + kTableBegin.size(), to - from - kTableBegin.size());
}

TEST(CalibrationConfigSchema, TheReadmeTableIsTheSchemas)
{
  const std::string path = std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/../README.md";
  std::ifstream file(path);
  ASSERT_TRUE(file.good()) << path;
  std::stringstream readme;
  readme << file.rdbuf();
  // On a change of the schema, run this test with ODOMETRY_CALIBRATION_WRITE_EXPECTED=1: it
  // writes the new table into README.md (between the markers), to be reviewed and committed.
  const std::string table = readmeTable(readme.str());
  if (std::getenv("ODOMETRY_CALIBRATION_WRITE_EXPECTED") != nullptr &&
      table != "(markers missing)") {
    std::string updated = readme.str();
    const std::size_t at = updated.find(kTableBegin) + kTableBegin.size();
    updated.replace(at, table.size(), formatConfigSchemaMarkdown());
    std::ofstream(path) << updated;
  }
  EXPECT_EQ(table, formatConfigSchemaMarkdown());
  // Every configuration key the README names elsewhere (`section.key`) exists.
  std::set<std::string> keys, sections;
  for (const ConfigKeySpec* spec : calibrationConfigSpecs()) {
    keys.insert(spec->key);
    for (std::size_t dot = spec->key.find('.'); dot != std::string::npos;
         dot = spec->key.find('.', dot + 1))
      sections.insert(spec->key.substr(0, dot));
  }
  const std::regex named("`((?:joints\\[\\]|[a-z_]+)(?:\\.[a-z_]+)+)(?::[^`]*)?`");
  const std::string text = readme.str();
  for (std::sregex_iterator it(text.begin(), text.end(), named), done; it != done; ++it) {
    const std::string key = (*it)[1];
    const std::string section = key.substr(0, key.find('.'));
    if (sections.count(section) > 0) {
      EXPECT_TRUE(keys.count(key) > 0 || sections.count(key) > 0) << key << " in README.md";
    }
  }
}

}  // namespace
}  // namespace odometry_calibration
