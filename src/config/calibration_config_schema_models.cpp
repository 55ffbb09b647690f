// The models' keys of calibration_config_schema.h: start values and fit options of diff_drive,
// tricycle, mecanum, skid_steer and base_odometry, the linear model's and the Gaussian process's
// options.
#include <cmath>

#include "odometry_calibration/config/calibration_config_schema.h"
#include "odometry_calibration/gp/gp_options.h"

namespace odometry_calibration {
namespace {

using Entry = ConfigSchemaEntry<CalibrationConfig>;

/// A field of the target, for both the setter and the getter (const or not).
#define AT(member)          \
  [](auto& target) -> auto& \
  {                         \
    return target.member;   \
  }

/// A wheel's radius: from a 1 mm micro-robot's wheel to a 5 m mining truck's tyre.
const ConfigRange kRadiusRange = rangeClosed(1e-3, 5.0);
/// A wheel separation, wheelbase or half wheelbase + half track: 1 cm to 50 m.
const ConfigRange kTrackRange = rangeClosed(0.01, 50.0);

/// A model section's `sensor_pose: [x, y, theta]`, the start value of the sensor's pose.
template <typename Field>
Entry sensorPose(const std::string& key, Field field)
{
  Entry e{configKeySpec(key, ConfigType::kDoubleList, "m, m, rad",
                        "sensor pose in base_link [x, y, theta]: start value and matcher guesses"),
          {},
          {}};
  e.spec.range = rangeClosed(-100.0, 100.0);
  e.spec.min_size = e.spec.max_size = 3;
  e.spec.default_value = std::vector<double>{0.0, 0.0, 0.0};
  e.set = [field](CalibrationConfig& c, const ConfigValue& v) {
    const auto& p = std::get<std::vector<double>>(v);
    field(c) = Pose2(p[0], p[1], p[2]);
  };
  e.get = [field](const CalibrationConfig& c) {
    return ConfigValue(std::vector<double>{field(c).x(), field(c).y(), field(c).theta()});
  };
  return e;
}

/// The name of joint `index` of `config`, "" when there is none.
ConfigValue jointName(const CalibrationConfig& config, int index)
{
  const bool valid = index >= 0 && static_cast<std::size_t>(index) < config.joints.size();
  return valid ? config.joints[static_cast<std::size_t>(index)].name : std::string();
}

ConfigValue jointNames(const CalibrationConfig& config, const std::vector<int>& indices)
{
  std::vector<std::string> names;
  for (int index : indices)
    names.push_back(std::get<std::string>(jointName(config, index)));
  return names;
}

Entry jointKey(const std::string& key, const char* default_text, const char* description,
               int (*index)(const CalibrationConfig&))
{
  ConfigKeySpec s = configKeySpec(key, ConfigType::kString, "", description);
  s.allow_empty = false;
  return derivedEntry<CalibrationConfig>(
      s, default_text, [index](const CalibrationConfig& c) { return jointName(c, index(c)); });
}

Entry jointList(const std::string& key, const char* default_text, const char* description,
                std::vector<int> SkidSteerOptions::*indices)
{
  ConfigKeySpec s = configKeySpec(key, ConfigType::kStringList, "", description);
  s.allow_empty = false;
  s.min_size = 1;
  return derivedEntry<CalibrationConfig>(s, default_text, [indices](const CalibrationConfig& c) {
    return jointNames(c, c.models.skid_steer.*indices);
  });
}

/// A fit's common options (`options` gives the model's options struct, or the part of it that
/// holds them): Huber threshold, iteration cap, global starts.
template <typename Options>
std::vector<Entry> fitOptions(const std::string& section, ConfigRange huber, const char* huber_note,
                              int yaw_starts, Options options)
{
  return {
      number<CalibrationConfig>(
          section + ".huber_threshold", 3.0, "sigma", huber,
          huber_note, [options](auto& c) -> auto& { return options(c).huber_threshold; }),
      integer<CalibrationConfig>(
          section + ".max_iterations", 500, rangeClosed(1, 10000),
          "Levenberg-Marquardt iteration cap per solve",
          [options](auto& c) -> auto& { return options(c).max_iterations; }),
      integer<CalibrationConfig>(
          section + ".yaw_starts", yaw_starts, rangeClosed(1, 360),
          "global starts: sensor yaws tried, 360/n deg apart (1: sensor_pose only)",
          [options](auto& c) -> auto& { return options(c).yaw_starts; }),
  };
}

constexpr ConfigRange kHuberRange{0.01, 100.0, false, false};

std::vector<Entry> diffDriveEntries()
{
  std::vector<Entry> entries = {
      jointKey("diff_drive.left_joint", "first joint", "left wheel joint",
               [](const CalibrationConfig& c) { return c.models.diff_drive.layout.left_index; }),
      jointKey("diff_drive.right_joint", "second joint", "right wheel joint",
               [](const CalibrationConfig& c) { return c.models.diff_drive.layout.right_index; }),
      [] {
        Entry radius =
            number<CalibrationConfig>("diff_drive.wheel_radius_m", 0.05, "m", kRadiusRange,
                                      "nominal wheel radius: start value and matcher guesses",
                                      AT(models.diff_drive.initial_left_radius_m));
        auto set = radius.set;
        radius.set = [set](CalibrationConfig& c, const ConfigValue& v) {
          set(c, v);
          c.models.diff_drive.initial_right_radius_m = std::get<double>(v);
        };
        return radius;
      }(),
      number<CalibrationConfig>("diff_drive.wheel_separation_m", 0.3, "m", kTrackRange,
                                "nominal wheel separation: start value and matcher guesses",
                                AT(models.diff_drive.initial_separation_m)),
      sensorPose("diff_drive.sensor_pose", AT(models.diff_drive.initial_T_base_sensor)),
  };
  appendEntries(entries,
                fitOptions("diff_drive", kHuberRange, "Huber threshold on a pair's whitened error",
                           8, AT(models.diff_drive)));
  return entries;
}

std::vector<Entry> tricycleEntries()
{
  std::vector<Entry> entries = {
      jointKey("tricycle.steering_joint", "first joint", "steering joint (kind: absolute)",
               [](const CalibrationConfig& c) { return c.models.tricycle.layout.steering_index; }),
      jointKey("tricycle.traction_joint", "second joint", "traction wheel joint (incremental)",
               [](const CalibrationConfig& c) { return c.models.tricycle.layout.traction_index; }),
      number<CalibrationConfig>("tricycle.steering_scale", 0.1, "", rangeClosed(1e-4, 100.0),
                                "Ks: steering angle per encoder angle (start value)",
                                AT(models.tricycle.initial.steering_scale)),
      number<CalibrationConfig>("tricycle.traction_scale_m_per_turn", 0.01, "m/turn",
                                rangeClosed(1e-6, 100.0),
                                "Kt: front-wheel travel per wheel turn (start value)",
                                AT(models.tricycle.initial.traction_scale_m_per_turn)),
      number<CalibrationConfig>("tricycle.axis_length_m", 1.0, "m", kTrackRange,
                                "a: front wheel to rear axle (start value)",
                                AT(models.tricycle.initial.axis_length_m)),
      number<CalibrationConfig>("tricycle.steering_offset_rad", 0.0, "rad",
                                rangeClosed(-M_PI, M_PI),
                                "ds: steering angle at a zero reading (start value)",
                                AT(models.tricycle.initial.steering_offset_rad)),
      sensorPose("tricycle.sensor_pose", AT(models.tricycle.initial.T_base_sensor)),
      number<CalibrationConfig>("tricycle.translation_sigma_m", 0.01, "m", rangeClosed(1e-6, 10.0),
                                "assumed sigma of a measured displacement's x, y",
                                AT(models.tricycle.calibration.translation_sigma_m)),
      number<CalibrationConfig>("tricycle.rotation_sigma_rad", 0.01, "rad", rangeClosed(1e-6, M_PI),
                                "assumed sigma of a measured displacement's heading",
                                AT(models.tricycle.calibration.rotation_sigma_rad)),
  };
  appendEntries(entries,
                fitOptions("tricycle", rangeClosed(0.0, 100.0),
                           "Huber threshold on a pair's whitened error (0: no robust loss)", 1,
                           AT(models.tricycle.calibration)));
  return entries;
}

int mecanumIndex(const CalibrationConfig& c, int wheel)
{
  const MecanumEncoderLayout& l = c.models.mecanum.layout;
  const int indices[4] = {l.front_left_index, l.front_right_index, l.rear_left_index,
                          l.rear_right_index};
  return indices[wheel];
}

std::vector<Entry> mecanumEntries()
{
  ConfigKeySpec radii =
      configKeySpec("mecanum.wheel_radii_m", ConfigType::kDoubleList, "m",
                    "nominal radii [front_left, front_right, rear_left, rear_right]");
  radii.range = kRadiusRange;
  radii.min_size = radii.max_size = 4;
  std::vector<Entry> entries = {
      jointKey("mecanum.front_left_joint", "first joint", "front-left wheel joint",
               [](const CalibrationConfig& c) { return mecanumIndex(c, 0); }),
      jointKey("mecanum.front_right_joint", "second joint", "front-right wheel joint",
               [](const CalibrationConfig& c) { return mecanumIndex(c, 1); }),
      jointKey("mecanum.rear_left_joint", "third joint", "rear-left wheel joint",
               [](const CalibrationConfig& c) { return mecanumIndex(c, 2); }),
      jointKey("mecanum.rear_right_joint", "fourth joint", "rear-right wheel joint",
               [](const CalibrationConfig& c) { return mecanumIndex(c, 3); }),
      [] {
        Entry radius = number<CalibrationConfig>(
            "mecanum.wheel_radius_m", 0.05, "m", kRadiusRange,
            "nominal radius of every wheel (start value, matcher guesses)",
            AT(models.mecanum.initial_radius_m[0]));
        radius.set = [](CalibrationConfig& c, const ConfigValue& v) {
          c.models.mecanum.initial_radius_m.fill(std::get<double>(v));
        };
        return radius;
      }(),
      derivedEntry<CalibrationConfig>(radii, "wheel_radius_m for each",
                                      [](const CalibrationConfig& c) {
                                        const auto& r = c.models.mecanum.initial_radius_m;
                                        return ConfigValue(std::vector<double>(r.begin(), r.end()));
                                      }),
      number<CalibrationConfig>("mecanum.lx_plus_ly_m", 0.35, "m", kTrackRange,
                                "nominal half wheelbase + half track (start value)",
                                AT(models.mecanum.initial_lx_plus_ly_m)),
      sensorPose("mecanum.sensor_pose", AT(models.mecanum.initial_T_base_sensor)),
  };
  appendEntries(entries,
                fitOptions("mecanum", kHuberRange, "Huber threshold on a pair's whitened error", 8,
                           AT(models.mecanum)));
  return entries;
}

std::vector<Entry> skidSteerEntries()
{
  std::vector<Entry> entries = {
      jointList("skid_steer.left_joints", "incremental joints named *left*",
                "the left side's wheel joints (averaged)", &SkidSteerOptions::left_indices),
      jointList("skid_steer.right_joints", "incremental joints named *right*",
                "the right side's wheel joints (averaged)", &SkidSteerOptions::right_indices),
      number<CalibrationConfig>("skid_steer.wheel_radius_m", 0.1, "m", kRadiusRange,
                                "geometric wheel radius", AT(models.skid_steer.wheel_radius_m)),
      number<CalibrationConfig>("skid_steer.wheel_separation_m", 0.5, "m", kTrackRange,
                                "geometric track width, wheel centre to centre",
                                AT(models.skid_steer.wheel_separation_m)),
      sensorPose("skid_steer.sensor_pose", AT(models.skid_steer.initial_T_base_sensor)),
  };
  appendEntries(entries,
                fitOptions("skid_steer", kHuberRange, "Huber threshold on a pair's whitened error",
                           8, AT(models.skid_steer)));
  return entries;
}

std::vector<Entry> baseOdometryEntries()
{
  std::vector<Entry> entries = {
      number<CalibrationConfig>("base_odometry.translation_scale", 1.0, "",
                                rangeClosed(0.01, 100.0),
                                "k_t: true translation per reported one (start value)",
                                AT(models.base_odometry.initial_translation_scale)),
      number<CalibrationConfig>("base_odometry.rotation_scale", 1.0, "", rangeClosed(0.01, 100.0),
                                "k_r: true rotation per reported one (start value)",
                                AT(models.base_odometry.initial_rotation_scale)),
      sensorPose("base_odometry.sensor_pose", AT(models.base_odometry.initial_T_base_sensor)),
  };
  appendEntries(entries, fitOptions("base_odometry", kHuberRange,
                                    "Huber threshold on a pair's whitened error", 8,
                                    AT(models.base_odometry)));
  return entries;
}

std::vector<Entry> linearAndGpEntries()
{
  return {
      number<CalibrationConfig>("linear.huber_threshold", 1.345, "sigma", kHuberRange,
                                "Huber threshold on scaled residuals",
                                AT(models.linear.huber_threshold)),
      number<CalibrationConfig>(
          "linear.outlier_threshold", 5.0, "sigma", rangeClosed(1.0, 1000.0),
          "pairs beyond this many robust sigma are rejected (> huber_threshold)",
          AT(models.linear.outlier_threshold)),
      choice<CalibrationConfig>(
          "gp.kernel", "rbf", {"rbf", "linear", "rbf+linear"}, "covariance function per output",
          [](CalibrationConfig& c, const std::string& v) {
            c.models.gp.kernel = parseGpKernelType(v);
          },
          [](const CalibrationConfig& c) { return toString(c.models.gp.kernel); }),
      choice<CalibrationConfig>(
          "gp.mean", "linear", {"linear", "zero"}, "prior mean: linear (C delta) or zero",
          [](CalibrationConfig& c, const std::string& v) {
            c.models.gp.mean = parseGpMeanFunction(v);
          },
          [](const CalibrationConfig& c) { return toString(c.models.gp.mean); }),
      integer<CalibrationConfig>("gp.starts", 4, rangeClosed(1, 64),
                                 "hyperparameter optimisation starts per output",
                                 AT(models.gp.starts)),
      integer<CalibrationConfig>(
          "gp.max_exact_pairs", 3000, rangeClosed(1, 10000),
          "distinct inputs beyond which the GP is sparse (the exact GP is O(n^3))",
          AT(models.gp.max_exact_pairs)),
      integer<CalibrationConfig>("gp.inducing_points", 128, rangeClosed(1, 2000),
                                 "inducing inputs of the sparse GP", AT(models.gp.inducing_points)),
      number<CalibrationConfig>("gp.outlier_threshold", 5.0, "sigma", rangeClosed(0.0, 1000.0),
                                "pairs beyond this many sigma are outliers (0: keep every pair)",
                                AT(models.gp.outlier_threshold)),
  };
}
}  // namespace

const std::vector<ConfigSchemaEntry<CalibrationConfig>>& modelConfigSchema()
{
  static const std::vector<Entry> entries = [] {
    std::vector<Entry> all;
    for (auto section : {diffDriveEntries, tricycleEntries, mecanumEntries, skidSteerEntries,
                         baseOdometryEntries, linearAndGpEntries})
      appendEntries(all, section());
    return all;
  }();
  return entries;
}

}  // namespace odometry_calibration
