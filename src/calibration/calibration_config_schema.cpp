// The declarations of calibration_config_schema.h. Ranges: values a physical robot and sensor
// can have (positive lengths, keyframe intervals of at least a fast sensor's period, 10 ms),
// and upper bounds on counts (iterations, starts, inducing points) that keep a fit's memory and
// time bounded.
#include "odometry_calibration/calibration/calibration_config_schema.h"

#include <cmath>
#include <type_traits>

#include "odometry_calibration/models/gp_options.h"

namespace odometry_calibration {
namespace {

using Entry = ConfigSchemaEntry<CalibrationConfig>;
using JointEntry = ConfigSchemaEntry<JointConfig>;

/// A field of the target, for both the setter and the getter (const or not).
#define AT(member)          \
  [](auto& target) -> auto& \
  {                         \
    return target.member;   \
  }

ConfigRange closed(double min, double max)
{
  return {min, max, false, false};
}

ConfigRange positive(double max)
{
  return {0.0, max, true, false};
}

ConfigRange open(double min, double max)
{
  return {min, max, true, true};
}

ConfigKeySpec spec(const std::string& key, ConfigType type, const char* unit,
                   const char* description)
{
  ConfigKeySpec s;
  s.key = key;
  s.type = type;
  s.unit = unit;
  s.description = description;
  return s;
}

template <typename Target = CalibrationConfig, typename Field>
ConfigSchemaEntry<Target> number(const std::string& key, double value, const char* unit,
                                 ConfigRange range, const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{spec(key, ConfigType::kDouble, unit, description), {}, {}};
  e.spec.range = range;
  e.spec.default_value = value;
  e.set = [field](Target& t, const ConfigValue& v) { field(t) = std::get<double>(v); };
  e.get = [field](const Target& t) { return ConfigValue(static_cast<double>(field(t))); };
  return e;
}

template <typename Target = CalibrationConfig, typename Field>
ConfigSchemaEntry<Target> integer(const std::string& key, long long value, ConfigRange range,
                                  const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{spec(key, ConfigType::kInt, "", description), {}, {}};
  e.spec.range = range;
  e.spec.default_value = value;
  e.set = [field](Target& t, const ConfigValue& v) {
    field(t) = static_cast<std::decay_t<decltype(field(t))>>(std::get<long long>(v));
  };
  e.get = [field](const Target& t) { return ConfigValue(static_cast<long long>(field(t))); };
  return e;
}

template <typename Field>
Entry flag(const std::string& key, bool value, const char* description, Field field)
{
  Entry e{spec(key, ConfigType::kBool, "", description), {}, {}};
  e.spec.default_value = value;
  e.set = [field](CalibrationConfig& c, const ConfigValue& v) { field(c) = std::get<bool>(v); };
  e.get = [field](const CalibrationConfig& c) { return ConfigValue(field(c)); };
  return e;
}

template <typename Target = CalibrationConfig, typename Field>
ConfigSchemaEntry<Target> text(const std::string& key, const char* value, bool allow_empty,
                               const char* description, Field field)
{
  ConfigSchemaEntry<Target> e{spec(key, ConfigType::kString, "", description), {}, {}};
  e.spec.default_value = std::string(value);
  e.spec.allow_empty = allow_empty;
  e.set = [field](Target& t, const ConfigValue& v) { field(t) = std::get<std::string>(v); };
  e.get = [field](const Target& t) { return ConfigValue(field(t)); };
  return e;
}

/// A string among `choices` that sets an enum: `parse` turns the name into the value, `name`
/// the value into its name.
template <typename Target = CalibrationConfig, typename Parse, typename Name>
ConfigSchemaEntry<Target> choice(const std::string& key, const char* value,
                                 std::vector<std::string> choices, const char* description,
                                 Parse parse, Name name)
{
  ConfigSchemaEntry<Target> e{spec(key, ConfigType::kString, "", description), {}, {}};
  e.spec.default_value = std::string(value);
  e.spec.choices = std::move(choices);
  e.set = [parse](Target& t, const ConfigValue& v) { parse(t, std::get<std::string>(v)); };
  e.get = [name](const Target& t) { return ConfigValue(std::string(name(t))); };
  return e;
}

/// A key whose default depends on other keys (`default_text`): the parser resolves it.
Entry derived(ConfigKeySpec s, const char* default_text,
              std::function<ConfigValue(const CalibrationConfig&)> get)
{
  s.default_text = default_text;
  return Entry{std::move(s), {}, std::move(get)};
}

/// A model section's `sensor_pose: [x, y, theta]`, the start value of the sensor's pose.
template <typename Field>
Entry sensorPose(const std::string& key, Field field)
{
  Entry e{spec(key, ConfigType::kDoubleList, "m, m, rad",
               "sensor pose in base_link [x, y, theta]: start value and matcher guesses"),
          {},
          {}};
  e.spec.range = closed(-100.0, 100.0);
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
  ConfigKeySpec s = spec(key, ConfigType::kString, "", description);
  s.allow_empty = false;
  return derived(s, default_text,
                 [index](const CalibrationConfig& c) { return jointName(c, index(c)); });
}

Entry jointList(const std::string& key, const char* default_text, const char* description,
                std::vector<int> SkidSteerOptions::*indices)
{
  ConfigKeySpec s = spec(key, ConfigType::kStringList, "", description);
  s.allow_empty = false;
  s.min_size = 1;
  return derived(s, default_text, [indices](const CalibrationConfig& c) {
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
      number(
          section + ".huber_threshold", 3.0, "sigma", huber,
          huber_note, [options](auto& c) -> auto& { return options(c).huber_threshold; }),
      integer(
          section + ".max_iterations", 500, closed(1, 10000),
          "Levenberg-Marquardt iteration cap per solve",
          [options](auto& c) -> auto& { return options(c).max_iterations; }),
      integer(
          section + ".yaw_starts", yaw_starts, closed(1, 360),
          "global starts: sensor yaws tried, 360/n deg apart (1: sensor_pose only)",
          [options](auto& c) -> auto& { return options(c).yaw_starts; }),
  };
}

void append(std::vector<Entry>& entries, std::vector<Entry> more)
{
  for (Entry& entry : more)
    entries.push_back(std::move(entry));
}

std::vector<JointEntry> jointEntries()
{
  JointEntry name = text<JointConfig>("joints[].name", "", false,
                                      "joint name in sensor_msgs/JointState", AT(name));
  name.spec.default_value.reset();
  name.spec.default_text = "required";
  return {
      name,
      choice<JointConfig>(
          "joints[].kind", "incremental", {"incremental", "absolute"},
          "incremental (a wheel's cumulative count) or absolute (a steering angle)",
          [](JointConfig& j, const std::string& v) {
            j.kind = v == "absolute" ? EncoderKind::kAbsolute : EncoderKind::kIncremental;
          },
          [](const JointConfig& j) {
            return j.kind == EncoderKind::kAbsolute ? "absolute" : "incremental";
          }),
      number<JointConfig>("joints[].units_per_turn", 2.0 * M_PI, "units/turn", positive(1e9),
                          "position units per joint turn: ticks, or 2 pi for radians",
                          AT(units_per_turn)),
      integer<JointConfig>("joints[].counter_bits", 0, closed(0, 52),
                           "incremental: the raw counter wraps at 2^bits (0: never)",
                           AT(counter_bits)),
      number<JointConfig>("joints[].max_turns_per_s", 50.0, "turns/s", closed(0.0, 1e4),
                          "a faster step between two readings is an encoder glitch (0: off)",
                          AT(max_turns_per_s)),
      [] {
        JointEntry sign = number<JointConfig>(
            "joints[].sign", 1.0, "", closed(-1.0, 1.0),
            "-1 when the joint counts backwards while the robot drives forward", AT(sign));
        sign.spec.values = {1.0, -1.0};
        return sign;
      }(),
  };
}

std::vector<Entry> topLevelEntries()
{
  ConfigKeySpec compare = spec("compare_models", ConfigType::kStringList, "",
                               "further models fitted and scored for the comparison table");
  compare.choices = knownModelNames();
  compare.max_size = 16;
  compare.default_value = std::vector<std::string>{};
  ConfigKeySpec prior = spec("prior_model", ConfigType::kString, "",
                             "start values of the matcher's guesses, the node's nominal "
                             "odometry and the tables' nominal row (none: no guess)");
  prior.choices = {"none", "diff_drive", "tricycle", "mecanum", "skid_steer"};
  return {
      text("joint_state_topic", "/joint_states", false, "sensor_msgs/JointState topic",
           AT(joint_state_topic)),
      choice(
          "model", "diff_drive", knownModelNames(), "model fitted",
          [](CalibrationConfig& c, const std::string& v) { c.model = v; },
          [](const CalibrationConfig& c) { return c.model; }),
      Entry{compare,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.compare_models = std::get<std::vector<std::string>>(v);
            },
            [](const CalibrationConfig& c) { return ConfigValue(c.compare_models); }},
      derived(prior, "the model if diff_drive, tricycle, mecanum or skid_steer, else diff_drive",
              [](const CalibrationConfig& c) { return ConfigValue(c.prior_model); }),
      text("output_directory", "odometry_calibration_results", false,
           "where the result files go (relative: the working directory)", AT(output_directory)),
  };
}

std::vector<Entry> egoMotionEntries()
{
  return {
      choice(
          "ego_motion.source", "scan", {"scan", "cloud", "odometry", "pose"},
          "scan (LaserScan + PLICP), cloud (PointCloud2 -> scan + PLICP), odometry "
          "(nav_msgs/Odometry) or pose (geometry_msgs/PoseStamped) of the sensor",
          [](CalibrationConfig& c, const std::string& v) {
            c.ego_motion = v == "cloud"      ? EgoMotionSource::kCloud
                           : v == "odometry" ? EgoMotionSource::kOdometry
                           : v == "pose"     ? EgoMotionSource::kPose
                                             : EgoMotionSource::kScan;
          },
          [](const CalibrationConfig& c) {
            const char* names[] = {"scan", "odometry", "pose", "cloud"};
            return names[static_cast<int>(c.ego_motion)];
          }),
      text("ego_motion.scan_topic", "/scan", false, "sensor_msgs/LaserScan topic (source scan)",
           AT(scan_topic)),
      text("ego_motion.topic", "", true, "topic of the cloud, odometry or pose source",
           AT(ego_motion_topic)),
      number("ego_motion.sigma_m", 0.005, "m", closed(1e-6, 1.0),
             "odometry/pose source: sigma of a displacement's x, y", AT(ego_motion_sigma_m)),
      number("ego_motion.sigma_rad", 0.002, "rad", closed(1e-6, 1.0),
             "odometry/pose source: sigma of a displacement's heading", AT(ego_motion_sigma_rad)),
  };
}

std::vector<Entry> cloudFilterEntries()
{
  ConfigKeySpec band = spec("ego_motion.cloud.band_m", ConfigType::kDoubleList, "m",
                            "height band [min, max] about the ground-parallel plane through "
                            "the sensor");
  band.range = closed(-100.0, 100.0);
  band.min_size = band.max_size = 2;
  band.default_value = std::vector<double>{-0.3, 0.3};
  return {
      Entry{band,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.cloud.band_min_m = std::get<std::vector<double>>(v)[0];
              c.cloud.band_max_m = std::get<std::vector<double>>(v)[1];
            },
            [](const CalibrationConfig& c) {
              return ConfigValue(std::vector<double>{c.cloud.band_min_m, c.cloud.band_max_m});
            }},
      number("ego_motion.cloud.roll_rad", 0.0, "rad", open(-M_PI / 2, M_PI / 2),
             "the lidar's roll against the ground (the cloud is levelled first)",
             AT(cloud.roll_rad)),
      number("ego_motion.cloud.pitch_rad", 0.0, "rad", open(-M_PI / 2, M_PI / 2),
             "the lidar's pitch against the ground (+: nose down)", AT(cloud.pitch_rad)),
      number("ego_motion.cloud.voxel_size_m", 0.05, "m", closed(0.0, 10.0),
             "VoxelGrid leaf size (0: off)", AT(cloud.voxel_size_m)),
      integer("ego_motion.cloud.outlier_neighbours", 0, closed(0, 1000),
              "StatisticalOutlierRemoval's k (0: off)", AT(cloud.outlier_neighbours)),
      number("ego_motion.cloud.outlier_stddev", 1.0, "sigma", positive(100.0),
             "its threshold: mean distance + this many sigma", AT(cloud.outlier_stddev)),
      number("ego_motion.cloud.range_min_m", 0.3, "m", closed(0.0, 1000.0),
             "nearer points (the robot itself) dropped", AT(cloud.range_min_m)),
      number("ego_motion.cloud.range_max_m", 60.0, "m", positive(1000.0), "farther points dropped",
             AT(cloud.range_max_m)),
  };
}

std::vector<Entry> cloudScanEntries()
{
  return {
      choice(
          "ego_motion.cloud.scan_from", "bins", {"bins", "points"},
          "bins: nearest point per bearing bin; points: every voxel at its own bearing",
          [](CalibrationConfig& c, const std::string& v) { c.cloud.scan_from = scanFromName(v); },
          [](const CalibrationConfig& c) { return toString(c.cloud.scan_from); }),
      number("ego_motion.cloud.angular_resolution_rad", 0.00349, "rad", positive(0.1),
             "bearing bin, one ray of the scan (scan_from: bins)",
             AT(cloud.angular_resolution_rad)),
      text("ego_motion.cloud.point_time_field", "", true,
           "per-point time field (\"\": the first of time, t, timestamp)",
           AT(cloud.point_times.field)),
      choice(
          "ego_motion.cloud.point_time_unit", "auto", {"auto", "s", "ms", "us", "ns"},
          "unit of the per-point times (auto: ns for integer fields, else s unless > 1e12)",
          [](CalibrationConfig& c, const std::string& v) {
            c.cloud.point_times.unit = pointTimeUnitName(v);
          },
          [](const CalibrationConfig& c) { return toString(c.cloud.point_times.unit); }),
      choice(
          "ego_motion.cloud.point_time_reference", "auto", {"auto", "relative", "absolute"},
          "relative (after the stamp) or absolute times (auto: the median's nearer one)",
          [](CalibrationConfig& c, const std::string& v) {
            c.cloud.point_times.reference = pointTimeReferenceName(v);
          },
          [](const CalibrationConfig& c) { return toString(c.cloud.point_times.reference); }),
      number("ego_motion.cloud.point_time_limit_s", 0.5, "s", positive(10.0),
             "a time farther from the stamp: the cloud is used without times",
             AT(cloud.point_times.limit_s)),
  };
}

std::vector<Entry> keyframeEntries()
{
  return {
      number("keyframes.interval_s", 0.5, "s", closed(0.01, 60.0),
             "keyframe spacing T; keep >= 0.3 s on real robots (stamp jitter biases shorter "
             "pairs)",
             AT(collector.keyframe_interval_s)),
      number("keyframes.min_translation_m", 0.0, "m", closed(0.0, 100.0),
             "minimum pair motion the prior model predicts (0: off); shorter intervals extended",
             AT(collector.min_translation_m)),
      number("keyframes.min_rotation_rad", 0.0, "rad", closed(0.0, 2 * M_PI),
             "minimum pair rotation the prior model predicts (0: off)",
             AT(collector.min_rotation_rad)),
      number("keyframes.time_offset_s", 0.0, "s", open(-5.0, 5.0),
             "encoder values taken at scan time + offset", AT(collector.time_offset_s)),
      number("keyframes.max_encoder_gap_s", 0.25, "s", closed(0.001, 60.0),
             "a pair with a longer encoder silence inside it is dropped",
             AT(collector.max_encoder_gap_s)),
      flag("keyframes.check_consistency", true,
           "compare each keyframe match with the composed consecutive matches",
           AT(collector.check_consistency)),
      number("keyframes.consistency_translation_m", 0.03, "m", closed(1e-4, 10.0),
             "largest disagreement of the two, translation",
             AT(collector.consistency_translation_m)),
      number("keyframes.consistency_rotation_rad", 0.02, "rad", closed(1e-4, M_PI),
             "largest disagreement of the two, rotation", AT(collector.consistency_rotation_rad)),
      flag("keyframes.estimate_time_offset", false,
           "search the encoder-sensor time offset in time_offset_search_s",
           AT(estimate_time_offset)),
  };
}

std::vector<Entry> keyframeListEntries()
{
  ConfigKeySpec search = spec("keyframes.time_offset_search_s", ConfigType::kDoubleList, "s",
                              "time offset search range [min, max]");
  search.range = open(-5.0, 5.0);
  search.min_size = search.max_size = 2;
  search.increasing = true;
  search.default_value = std::vector<double>{-0.4, 0.4};
  ConfigKeySpec fit = spec("keyframes.fit_intervals_s", ConfigType::kDoubleList, "s",
                           "candidate fit intervals chosen by time-blocked cross-validation "
                           "([]: fit the interval_s pairs)");
  fit.range = closed(0.01, 60.0);
  fit.max_size = 20;
  fit.increasing = true;
  fit.default_value = std::vector<double>{};
  return {
      Entry{search,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.time_offset_search_min_s = std::get<std::vector<double>>(v)[0];
              c.time_offset_search_max_s = std::get<std::vector<double>>(v)[1];
            },
            [](const CalibrationConfig& c) {
              return ConfigValue(
                  std::vector<double>{c.time_offset_search_min_s, c.time_offset_search_max_s});
            }},
      Entry{fit,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.fit_intervals_s = std::get<std::vector<double>>(v);
            },
            [](const CalibrationConfig& c) { return ConfigValue(c.fit_intervals_s); }},
  };
}

std::vector<Entry> scanMatchingEntries()
{
  return {
      number("scan_matching.max_correspondence_distance_m", 0.5, "m", positive(10.0),
             "farthest point-to-line correspondence",
             AT(collector.plicp.max_correspondence_distance_m)),
      integer("scan_matching.max_iterations", 50, closed(1, 1000), "PLICP iteration cap",
              AT(collector.plicp.max_iterations)),
      number("scan_matching.range_sigma_m", 0.01, "m", closed(1e-5, 1.0),
             "laser range noise, for the match covariance", AT(collector.plicp.range_sigma_m)),
      number("scan_matching.max_correction_translation_m", 0.5, "m", positive(100.0),
             "largest allowed correction of the initial guess, translation",
             AT(collector.plicp.max_correction_translation_m)),
      number("scan_matching.max_correction_rotation_rad", 0.5, "rad", positive(M_PI),
             "largest allowed correction of the initial guess, rotation",
             AT(collector.plicp.max_correction_rotation_rad)),
      integer("scan_matching.min_points", 20, closed(3, 100000),
              "fewest valid rays of a scan to match", AT(collector.plicp.min_points)),
      flag("scan_matching.compensate_sweep", true,
           "move each ray to the scan's stamp with the prior model's velocity over the sweep",
           AT(collector.compensate_sweep)),
      integer("scan_matching.segment_fallback_max_surface_points", 0, closed(0, 100000),
              "two-point segments only on surfaces of at most this many points (0: any)",
              AT(collector.plicp.line_fit.segment_fallback_max_surface_points)),
      number("scan_matching.veiling_min_angle_rad", 0.0, "rad",
             ConfigRange{0.0, M_PI / 2, false, true},
             "drop veiling points at depth steps seen below this angle (0: off)",
             AT(collector.plicp.line_fit.veiling_min_angle_rad)),
      number("scan_matching.trim_keep_fraction", 0.95, "", positive(1.0),
             "keep at most this fraction of the correspondences (the nearest)",
             AT(collector.plicp.trim_keep_fraction)),
  };
}

constexpr ConfigRange kHuberRange{0.0, 100.0, true, false};

std::vector<Entry> diffDriveEntries()
{
  std::vector<Entry> entries = {
      jointKey("diff_drive.left_joint", "first joint", "left wheel joint",
               [](const CalibrationConfig& c) { return c.models.diff_drive.layout.left_index; }),
      jointKey("diff_drive.right_joint", "second joint", "right wheel joint",
               [](const CalibrationConfig& c) { return c.models.diff_drive.layout.right_index; }),
      [] {
        Entry radius = number("diff_drive.wheel_radius_m", 0.05, "m", positive(5.0),
                              "nominal wheel radius: start value and matcher guesses",
                              AT(models.diff_drive.initial_left_radius_m));
        auto set = radius.set;
        radius.set = [set](CalibrationConfig& c, const ConfigValue& v) {
          set(c, v);
          c.models.diff_drive.initial_right_radius_m = std::get<double>(v);
        };
        return radius;
      }(),
      number("diff_drive.wheel_separation_m", 0.3, "m", positive(50.0),
             "nominal wheel separation: start value and matcher guesses",
             AT(models.diff_drive.initial_separation_m)),
      sensorPose("diff_drive.sensor_pose", AT(models.diff_drive.initial_T_base_sensor)),
  };
  append(entries,
         fitOptions("diff_drive", kHuberRange, "Huber threshold on a pair's whitened error", 8,
                    AT(models.diff_drive)));
  return entries;
}

std::vector<Entry> tricycleEntries()
{
  std::vector<Entry> entries = {
      jointKey("tricycle.steering_joint", "first joint", "steering joint (kind: absolute)",
               [](const CalibrationConfig& c) { return c.models.tricycle.layout.steering_index; }),
      jointKey("tricycle.traction_joint", "second joint", "traction wheel joint (incremental)",
               [](const CalibrationConfig& c) { return c.models.tricycle.layout.traction_index; }),
      number("tricycle.steering_scale", 0.1, "", positive(100.0),
             "Ks: steering angle per encoder angle (start value)",
             AT(models.tricycle.initial.steering_scale)),
      number("tricycle.traction_scale_m_per_turn", 0.01, "m/turn", positive(100.0),
             "Kt: front-wheel travel per wheel turn (start value)",
             AT(models.tricycle.initial.traction_scale_m_per_turn)),
      number("tricycle.axis_length_m", 1.0, "m", positive(50.0),
             "a: front wheel to rear axle (start value)",
             AT(models.tricycle.initial.axis_length_m)),
      number("tricycle.steering_offset_rad", 0.0, "rad", closed(-M_PI, M_PI),
             "ds: steering angle at a zero reading (start value)",
             AT(models.tricycle.initial.steering_offset_rad)),
      sensorPose("tricycle.sensor_pose", AT(models.tricycle.initial.T_base_sensor)),
      number("tricycle.translation_sigma_m", 0.01, "m", closed(1e-6, 10.0),
             "assumed sigma of a measured displacement's x, y",
             AT(models.tricycle.calibration.translation_sigma_m)),
      number("tricycle.rotation_sigma_rad", 0.01, "rad", closed(1e-6, M_PI),
             "assumed sigma of a measured displacement's heading",
             AT(models.tricycle.calibration.rotation_sigma_rad)),
  };
  append(entries, fitOptions("tricycle", closed(0.0, 100.0),
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
  ConfigKeySpec radii = spec("mecanum.wheel_radii_m", ConfigType::kDoubleList, "m",
                             "nominal radii [front_left, front_right, rear_left, rear_right]");
  radii.range = positive(5.0);
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
        Entry radius = number("mecanum.wheel_radius_m", 0.05, "m", positive(5.0),
                              "nominal radius of every wheel (start value, matcher guesses)",
                              AT(models.mecanum.initial_radius_m[0]));
        radius.set = [](CalibrationConfig& c, const ConfigValue& v) {
          c.models.mecanum.initial_radius_m.fill(std::get<double>(v));
        };
        return radius;
      }(),
      derived(radii, "wheel_radius_m for each",
              [](const CalibrationConfig& c) {
                const auto& r = c.models.mecanum.initial_radius_m;
                return ConfigValue(std::vector<double>(r.begin(), r.end()));
              }),
      number("mecanum.lx_plus_ly_m", 0.35, "m", positive(50.0),
             "nominal half wheelbase + half track (start value)",
             AT(models.mecanum.initial_lx_plus_ly_m)),
      sensorPose("mecanum.sensor_pose", AT(models.mecanum.initial_T_base_sensor)),
  };
  append(entries, fitOptions("mecanum", kHuberRange, "Huber threshold on a pair's whitened error",
                             8, AT(models.mecanum)));
  return entries;
}

std::vector<Entry> skidSteerEntries()
{
  std::vector<Entry> entries = {
      jointList("skid_steer.left_joints", "incremental joints named *left*",
                "the left side's wheel joints (averaged)", &SkidSteerOptions::left_indices),
      jointList("skid_steer.right_joints", "incremental joints named *right*",
                "the right side's wheel joints (averaged)", &SkidSteerOptions::right_indices),
      number("skid_steer.wheel_radius_m", 0.1, "m", positive(5.0), "geometric wheel radius",
             AT(models.skid_steer.wheel_radius_m)),
      number("skid_steer.wheel_separation_m", 0.5, "m", positive(50.0),
             "geometric track width, wheel centre to centre",
             AT(models.skid_steer.wheel_separation_m)),
      sensorPose("skid_steer.sensor_pose", AT(models.skid_steer.initial_T_base_sensor)),
  };
  append(entries,
         fitOptions("skid_steer", kHuberRange, "Huber threshold on a pair's whitened error", 8,
                    AT(models.skid_steer)));
  return entries;
}

std::vector<Entry> linearAndGpEntries()
{
  return {
      number("linear.huber_threshold", 1.345, "sigma", kHuberRange,
             "Huber threshold on scaled residuals", AT(models.linear.huber_threshold)),
      number("linear.outlier_threshold", 5.0, "sigma", positive(1000.0),
             "pairs beyond this many robust sigma are rejected (> huber_threshold)",
             AT(models.linear.outlier_threshold)),
      choice(
          "gp.kernel", "rbf", {"rbf", "linear", "rbf+linear"}, "covariance function per output",
          [](CalibrationConfig& c, const std::string& v) {
            c.models.gp.kernel = parseGpKernelType(v);
          },
          [](const CalibrationConfig& c) { return toString(c.models.gp.kernel); }),
      choice(
          "gp.mean", "linear", {"linear", "zero"}, "prior mean: linear (C delta) or zero",
          [](CalibrationConfig& c, const std::string& v) {
            c.models.gp.mean = parseGpMeanFunction(v);
          },
          [](const CalibrationConfig& c) { return toString(c.models.gp.mean); }),
      integer("gp.starts", 4, closed(1, 64), "hyperparameter optimisation starts per output",
              AT(models.gp.starts)),
      integer("gp.max_exact_pairs", 3000, closed(1, 10000),
              "distinct inputs beyond which the GP is sparse (the exact GP is O(n^3))",
              AT(models.gp.max_exact_pairs)),
      integer("gp.inducing_points", 128, closed(1, 2000), "inducing inputs of the sparse GP",
              AT(models.gp.inducing_points)),
      number("gp.outlier_threshold", 5.0, "sigma", closed(0.0, 1000.0),
             "pairs beyond this many sigma are outliers (0: keep every pair)",
             AT(models.gp.outlier_threshold)),
  };
}

}  // namespace

const std::vector<ConfigSchemaEntry<JointConfig>>& jointConfigSchema()
{
  static const std::vector<JointEntry> entries = jointEntries();
  return entries;
}

const std::vector<ConfigSchemaEntry<CalibrationConfig>>& calibrationConfigSchema()
{
  static const std::vector<Entry> entries = [] {
    std::vector<Entry> all;
    for (auto section :
         {topLevelEntries, egoMotionEntries, cloudScanEntries, cloudFilterEntries, keyframeEntries,
          keyframeListEntries, scanMatchingEntries, diffDriveEntries, tricycleEntries,
          mecanumEntries, skidSteerEntries, linearAndGpEntries})
      append(all, section());
    return all;
  }();
  return entries;
}

std::vector<const ConfigKeySpec*> calibrationConfigSpecs()
{
  std::vector<const ConfigKeySpec*> specs;
  for (const auto& entry : jointConfigSchema())
    specs.push_back(&entry.spec);
  for (const auto& entry : calibrationConfigSchema())
    specs.push_back(&entry.spec);
  return specs;
}

}  // namespace odometry_calibration
