// The declarations of calibration_config_schema.h: the joints', the sensor's and the pairing's
// keys (the models' in calibration_config_schema_models.cpp). Ranges: values a physical robot and
// sensor can have (positive lengths, keyframe intervals of at least a fast sensor's period, 10 ms),
// and upper bounds on counts (iterations, starts, inducing points) that keep a fit's memory and
// time bounded. No positive key reaches down to 0: a value like 1e-300 is a typo, not a robot
// (an encoder resolution of 1e-3 units per turn already means a whole turn reads as 0.001).
#include "odometry_calibration/config/calibration_config_schema.h"

#include <cmath>

namespace odometry_calibration {
namespace {

using Entry = ConfigSchemaEntry<CalibrationConfig>;
using JointEntry = ConfigSchemaEntry<JointConfig>;
using SourceEntry = ConfigSchemaEntry<EgoMotionSourceConfig>;

/// A field of the target, for both the setter and the getter (const or not).
#define AT(member)          \
  [](auto& target) -> auto& \
  {                         \
    return target.member;   \
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
      number<JointConfig>(
          "joints[].units_per_turn", 2.0 * M_PI, "units/turn", rangeClosed(1e-3, 1e9),
          "position units per joint turn: ticks, or 2 pi for radians", AT(units_per_turn)),
      integer<JointConfig>("joints[].counter_bits", 0, rangeClosed(0, 52),
                           "incremental: the raw counter wraps at 2^bits (0: never)",
                           AT(counter_bits)),
      number<JointConfig>("joints[].max_turns_per_s", 50.0, "turns/s", rangeClosed(0.0, 1e4),
                          "a faster step between two readings is an encoder glitch (0: off)",
                          AT(max_turns_per_s)),
      [] {
        JointEntry sign = number<JointConfig>(
            "joints[].sign", 1.0, "", rangeClosed(-1.0, 1.0),
            "-1 when the joint counts backwards while the robot drives forward", AT(sign));
        sign.spec.values = {1.0, -1.0};
        return sign;
      }(),
  };
}

/// The source types' names, in EgoMotionSource's order.
const char* sourceTypeName(EgoMotionSource type)
{
  const char* names[] = {"scan", "odometry", "pose", "cloud"};
  return names[static_cast<int>(type)];
}

EgoMotionSource sourceType(const std::string& name)
{
  return name == "cloud"      ? EgoMotionSource::kCloud
         : name == "odometry" ? EgoMotionSource::kOdometry
         : name == "pose"     ? EgoMotionSource::kPose
                              : EgoMotionSource::kScan;
}

std::vector<SourceEntry> sourceEntries()
{
  SourceEntry topic = text<EgoMotionSourceConfig>(
      "ego_motion.sources[].topic", "", false,
      "the source's topic (several sources, each paired with the encoders)", AT(topic));
  topic.spec.default_value.reset();
  topic.spec.default_text = "required";
  SourceEntry offset = number<EgoMotionSourceConfig>(
      "ego_motion.sources[].time_offset_s", 0.0, "s", rangeOpen(-5.0, 5.0),
      "this source's encoder time offset (encoders at its stamp + this)", AT(time_offset_s));
  offset.spec.default_value.reset();
  offset.spec.default_text = "keyframes.time_offset_s";
  SourceEntry pose{
      configKeySpec("ego_motion.sources[].sensor_pose", ConfigType::kDoubleList, "m, m, rad",
                    "this sensor's pose in base_link [x, y, theta]: its start value "
                    "and matcher guesses"),
      [](EgoMotionSourceConfig& c, const ConfigValue& v) {
        c.sensor_pose = std::get<std::vector<double>>(v);
      },
      [](const EgoMotionSourceConfig& c) { return ConfigValue(c.sensor_pose); }};
  pose.spec.range = rangeClosed(-100.0, 100.0);
  pose.spec.min_size = pose.spec.max_size = 3;
  pose.spec.default_text = "the model section's sensor_pose";
  return {
      topic,
      choice<EgoMotionSourceConfig>(
          "ego_motion.sources[].type", "scan", {"scan", "cloud", "odometry", "pose"},
          "what the topic carries, as ego_motion.source",
          [](EgoMotionSourceConfig& c, const std::string& v) { c.type = sourceType(v); },
          [](const EgoMotionSourceConfig& c) { return sourceTypeName(c.type); }),
      text<EgoMotionSourceConfig>(
          "ego_motion.sources[].frame", "", true,
          "the sensor's frame until its messages name theirs, which then win "
          "(base_link -> frame); the health monitor's name for it",
          AT(frame)),
      offset,
      pose,
      text<EgoMotionSourceConfig>("ego_motion.sources[].publisher", "", true,
                                  "node whose messages on the topic are used when two publish it "
                                  "(empty: one publisher only, a second is refused)",
                                  AT(publisher)),
  };
}

std::vector<Entry> topLevelEntries()
{
  ConfigKeySpec compare =
      configKeySpec("compare_models", ConfigType::kStringList, "",
                    "further models fitted and scored for the comparison table");
  compare.choices = knownModelNames();
  compare.max_size = 16;
  compare.default_value = std::vector<std::string>{};
  ConfigKeySpec prior = configKeySpec("prior_model", ConfigType::kString, "",
                                      "start values of the matcher's guesses, the node's nominal "
                                      "odometry and the tables' nominal row (none: no guess)");
  prior.choices = {"none", "diff_drive", "tricycle", "mecanum", "skid_steer", "base_odometry"};
  return {
      text<CalibrationConfig>("joint_state_topic", "/joint_states", false,
                              "sensor_msgs/JointState topic", AT(joint_state_topic)),
      text<CalibrationConfig>("joint_state_publisher", "", true,
                              "node whose JointState is used when two publish the joints (empty: "
                              "one publisher only, a second is refused)",
                              AT(joint_state_publisher)),
      choice<CalibrationConfig>(
          "model", "diff_drive", knownModelNames(), "model fitted",
          [](CalibrationConfig& c, const std::string& v) { c.model = v; },
          [](const CalibrationConfig& c) { return c.model; }),
      Entry{compare,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.compare_models = std::get<std::vector<std::string>>(v);
            },
            [](const CalibrationConfig& c) { return ConfigValue(c.compare_models); }},
      derivedEntry<CalibrationConfig>(
          prior,
          "the model if diff_drive, tricycle, mecanum or skid_steer; base_odometry with "
          "wheels.source odometry; else diff_drive",
          [](const CalibrationConfig& c) { return ConfigValue(c.prior_model); }),
      text<CalibrationConfig>("output_directory", "odometry_calibration_results", false,
                              "where the result files go (relative: the working directory)",
                              AT(output_directory)),
  };
}

/// The wheel sources' names, in WheelSource's order.
const char* wheelSourceName(WheelSource source)
{
  const char* names[] = {"joint_state", "ticks", "joint_velocity", "odometry"};
  return names[static_cast<int>(source)];
}

std::vector<Entry> wheelEntries()
{
  ConfigKeySpec topics =
      configKeySpec("wheels.topics", ConfigType::kStringList, "",
                    "ticks: one std_msgs topic per joint, in the joints' order (the messages carry "
                    "no stamp: the receive time live, the record time in a bag); odometry: the "
                    "base's nav_msgs/Odometry topic");
  topics.max_size = 16;
  topics.default_value = std::vector<std::string>{};
  return {
      choice<CalibrationConfig>(
          "wheels.source", "joint_state", {"joint_state", "ticks", "joint_velocity", "odometry"},
          "joint_state (JointState positions), ticks (a counter topic per joint), "
          "joint_velocity (JointState velocities only, integrated by the trapezoid rule) or "
          "odometry (the base's nav_msgs/Odometry: its pose increments in base_link)",
          [](CalibrationConfig& c, const std::string& v) {
            c.wheels.source = v == "ticks"            ? WheelSource::kTicks
                              : v == "joint_velocity" ? WheelSource::kJointVelocity
                              : v == "odometry"       ? WheelSource::kOdometry
                                                      : WheelSource::kJointState;
          },
          [](const CalibrationConfig& c) { return wheelSourceName(c.wheels.source); }),
      Entry{topics,
            [](CalibrationConfig& c, const ConfigValue& v) {
              c.wheels.topics = std::get<std::vector<std::string>>(v);
            },
            [](const CalibrationConfig& c) { return ConfigValue(c.wheels.topics); }},
      choice<CalibrationConfig>(
          "wheels.message_type", "std_msgs/Int32", wheelTickMessageTypes(),
          "ticks: the topics' type; joints[].counter_bits gives the counter's width within it "
          "(8 for an 8-bit counter carried in an Int16)",
          [](CalibrationConfig& c, const std::string& v) { c.wheels.message_type = v; },
          [](const CalibrationConfig& c) { return c.wheels.message_type; }),
      number<CalibrationConfig>("wheels.max_gap_s", 0.5, "s", rangeClosed(0.01, 60.0),
                                "ticks: an instant whose other wheel's samples lie further apart "
                                "is dropped; joint_velocity: a longer silence restarts the "
                                "integration",
                                AT(wheels.max_gap_s)),
  };
}

std::vector<Entry> egoMotionEntries()
{
  return {
      choice<CalibrationConfig>(
          "ego_motion.source", "scan", {"scan", "cloud", "odometry", "pose"},
          "scan (LaserScan + PLICP), cloud (PointCloud2 -> scan + PLICP), odometry "
          "(nav_msgs/Odometry) or pose (geometry_msgs/PoseStamped) of the sensor",
          [](CalibrationConfig& c, const std::string& v) { c.ego_motion = sourceType(v); },
          [](const CalibrationConfig& c) { return sourceTypeName(c.ego_motion); }),
      text<CalibrationConfig>("ego_motion.scan_topic", "/scan", false,
                              "sensor_msgs/LaserScan topic (source scan)", AT(scan_topic)),
      text<CalibrationConfig>("ego_motion.topic", "", true,
                              "topic of the cloud, odometry or pose source", AT(ego_motion_topic)),
      text<CalibrationConfig>("ego_motion.publisher", "", true,
                              "node whose ego-motion messages are used when two publish the topic "
                              "(empty: one publisher only, a second is refused)",
                              AT(ego_motion_publisher)),
      integer<CalibrationConfig>("ego_motion.max_scan_rays", 10000, rangeClosed(100, 1000000),
                                 "a LaserScan with more rays is skipped and counted (bounded "
                                 "memory and time per scan)",
                                 AT(max_scan_rays)),
      number<CalibrationConfig>("ego_motion.sigma_m", 0.005, "m", rangeClosed(1e-6, 1.0),
                                "odometry/pose source: sigma of a displacement's x, y",
                                AT(ego_motion_sigma_m)),
      number<CalibrationConfig>("ego_motion.sigma_rad", 0.002, "rad", rangeClosed(1e-6, 1.0),
                                "odometry/pose source: sigma of a displacement's heading",
                                AT(ego_motion_sigma_rad)),
  };
}

std::vector<Entry> cloudFilterEntries()
{
  ConfigKeySpec band =
      configKeySpec("ego_motion.cloud.band_m", ConfigType::kDoubleList, "m",
                    "height band [min, max] about the ground-parallel plane through "
                    "the sensor");
  band.range = rangeClosed(-100.0, 100.0);
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
      number<CalibrationConfig>(
          "ego_motion.cloud.roll_rad", 0.0, "rad", rangeOpen(-M_PI / 2, M_PI / 2),
          "the lidar's roll against the ground (the cloud is levelled first)", AT(cloud.roll_rad)),
      number<CalibrationConfig>(
          "ego_motion.cloud.pitch_rad", 0.0, "rad", rangeOpen(-M_PI / 2, M_PI / 2),
          "the lidar's pitch against the ground (+: nose down)", AT(cloud.pitch_rad)),
      number<CalibrationConfig>("ego_motion.cloud.voxel_size_m", 0.05, "m", rangeClosed(0.0, 10.0),
                                "VoxelGrid leaf size (0: off)", AT(cloud.voxel_size_m)),
      integer<CalibrationConfig>("ego_motion.cloud.outlier_neighbours", 0, rangeClosed(0, 1000),
                                 "StatisticalOutlierRemoval's k (0: off)",
                                 AT(cloud.outlier_neighbours)),
      number<CalibrationConfig>(
          "ego_motion.cloud.outlier_stddev", 1.0, "sigma", rangeClosed(0.01, 100.0),
          "its threshold: mean distance + this many sigma", AT(cloud.outlier_stddev)),
      number<CalibrationConfig>("ego_motion.cloud.range_min_m", 0.3, "m", rangeClosed(0.0, 100.0),
                                "nearer points (the robot itself) dropped", AT(cloud.range_min_m)),
      number<CalibrationConfig>("ego_motion.cloud.range_max_m", 60.0, "m", rangeClosed(0.1, 1000.0),
                                "farther points dropped", AT(cloud.range_max_m)),
  };
}

std::vector<Entry> cloudScanEntries()
{
  return {
      choice<CalibrationConfig>(
          "ego_motion.cloud.scan_from", "bins", {"bins", "points"},
          "bins: nearest point per bearing bin; points: every voxel at its own bearing",
          [](CalibrationConfig& c, const std::string& v) { c.cloud.scan_from = scanFromName(v); },
          [](const CalibrationConfig& c) { return toString(c.cloud.scan_from); }),
      number<CalibrationConfig>("ego_motion.cloud.angular_resolution_rad", 0.00349, "rad",
                                ConfigRange{1e-5, 0.1, true, false},
                                "bearing bin, one ray of the scan (scan_from: bins)",
                                AT(cloud.angular_resolution_rad)),
      text<CalibrationConfig>("ego_motion.cloud.point_time_field", "", true,
                              "per-point time field (\"\": the first of time, t, timestamp)",
                              AT(cloud.point_times.field)),
      choice<CalibrationConfig>(
          "ego_motion.cloud.point_time_unit", "auto", {"auto", "s", "ms", "us", "ns"},
          "unit of the per-point times (auto: ns for integer fields, else s unless > 1e12)",
          [](CalibrationConfig& c, const std::string& v) {
            c.cloud.point_times.unit = pointTimeUnitName(v);
          },
          [](const CalibrationConfig& c) { return toString(c.cloud.point_times.unit); }),
      choice<CalibrationConfig>(
          "ego_motion.cloud.point_time_reference", "auto", {"auto", "relative", "absolute"},
          "relative (after the stamp) or absolute times (auto: the median's nearer one)",
          [](CalibrationConfig& c, const std::string& v) {
            c.cloud.point_times.reference = pointTimeReferenceName(v);
          },
          [](const CalibrationConfig& c) { return toString(c.cloud.point_times.reference); }),
      number<CalibrationConfig>("ego_motion.cloud.point_time_limit_s", 0.5, "s",
                                rangeClosed(1e-4, 10.0),
                                "a time farther from the stamp: the cloud is used without times",
                                AT(cloud.point_times.limit_s)),
  };
}

std::vector<Entry> keyframeEntries()
{
  return {
      number<CalibrationConfig>(
          "keyframes.interval_s", 0.5, "s", rangeClosed(0.01, 60.0),
          "keyframe spacing T; keep >= 0.3 s on real robots (stamp jitter biases shorter "
          "pairs)",
          AT(collector.keyframe_interval_s)),
      number<CalibrationConfig>(
          "keyframes.min_translation_m", 0.0, "m", rangeClosed(0.0, 100.0),
          "minimum pair motion the prior model predicts (0: off); shorter intervals extended",
          AT(collector.min_translation_m)),
      number<CalibrationConfig>("keyframes.min_rotation_rad", 0.0, "rad",
                                rangeClosed(0.0, 2 * M_PI),
                                "minimum pair rotation the prior model predicts (0: off)",
                                AT(collector.min_rotation_rad)),
      number<CalibrationConfig>("keyframes.time_offset_s", 0.0, "s", rangeOpen(-5.0, 5.0),
                                "encoder values taken at scan time + offset",
                                AT(collector.time_offset_s)),
      number<CalibrationConfig>(
          "keyframes.max_encoder_gap_s", 0.0, "s", rangeClosed(0.0, 60.0),
          "a pair with a longer encoder silence inside it, or no reading this close to a "
          "keyframe, is dropped (0: derived from the readings, max(0.25 s, 2.5 x their median "
          "spacing))",
          AT(collector.max_encoder_gap_s)),
      flag<CalibrationConfig>("keyframes.check_consistency", true,
                              "compare each keyframe match with the composed consecutive matches",
                              AT(collector.check_consistency)),
      number<CalibrationConfig>(
          "keyframes.consistency_translation_m", 0.03, "m", rangeClosed(1e-4, 10.0),
          "largest disagreement of the two, translation", AT(collector.consistency_translation_m)),
      number<CalibrationConfig>(
          "keyframes.consistency_rotation_rad", 0.02, "rad", rangeClosed(1e-4, M_PI),
          "largest disagreement of the two, rotation", AT(collector.consistency_rotation_rad)),
      integer<CalibrationConfig>(
          "keyframes.consecutive_max_rays", 0, rangeClosed(0, 1000000),
          "the consecutive matches use at most this many rays, every "
          "k-th (0: all; else at least scan_matching.min_points; the keyframe matches use all)",
          AT(collector.consecutive_max_rays)),
      number<CalibrationConfig>(
          "keyframes.consecutive_min_spacing_s", 0.0, "s", rangeClosed(0.0, 60.0),
          "the consecutive matches skip scans less than this after the previous chained one "
          "(the keyframe scans always join; at most half of the keyframe interval is used; 0: "
          "every scan)",
          AT(collector.consecutive_min_spacing_s)),
      flag<CalibrationConfig>("keyframes.estimate_time_offset", true,
                              "search the encoder-sensor time offset in time_offset_search_s "
                              "(coarsely by heading correlation, then finely by refitting)",
                              AT(estimate_time_offset)),
  };
}

std::vector<Entry> keyframeListEntries()
{
  ConfigKeySpec search = configKeySpec("keyframes.time_offset_search_s", ConfigType::kDoubleList,
                                       "s", "time offset search range [min, max]");
  search.range = rangeOpen(-5.0, 5.0);
  search.min_size = search.max_size = 2;
  search.increasing = true;
  search.default_value = std::vector<double>{-2.0, 2.0};
  ConfigKeySpec fit =
      configKeySpec("keyframes.fit_intervals_s", ConfigType::kDoubleList, "s",
                    "candidate fit intervals chosen by time-blocked cross-validation "
                    "([]: fit the interval_s pairs)");
  fit.range = rangeClosed(0.01, 60.0);
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
      number<CalibrationConfig>(
          "scan_matching.max_correspondence_distance_m", 0.5, "m", rangeClosed(1e-3, 10.0),
          "farthest point-to-line correspondence (doubled, at most twice, for a "
          "match that finds too few at its guess)",
          AT(collector.plicp.max_correspondence_distance_m)),
      integer<CalibrationConfig>("scan_matching.max_iterations", 50, rangeClosed(1, 1000),
                                 "PLICP iteration cap", AT(collector.plicp.max_iterations)),
      number<CalibrationConfig>("scan_matching.range_sigma_m", 0.01, "m", rangeClosed(1e-5, 1.0),
                                "laser range noise, for the match covariance",
                                AT(collector.plicp.range_sigma_m)),
      number<CalibrationConfig>("scan_matching.max_correction_translation_m", 0.5, "m",
                                rangeClosed(1e-4, 100.0),
                                "largest allowed correction of the initial guess, translation",
                                AT(collector.plicp.max_correction_translation_m)),
      number<CalibrationConfig>("scan_matching.max_correction_rotation_rad", 0.5, "rad",
                                rangeClosed(1e-4, M_PI),
                                "largest allowed correction of the initial guess, rotation",
                                AT(collector.plicp.max_correction_rotation_rad)),
      integer<CalibrationConfig>("scan_matching.min_points", 20, rangeClosed(3, 100000),
                                 "fewest valid rays of a scan to match",
                                 AT(collector.plicp.min_points)),
      flag<CalibrationConfig>(
          "scan_matching.compensate_sweep", true,
          "move each ray to the scan's stamp with the prior model's velocity over the sweep",
          AT(collector.compensate_sweep)),
      integer<CalibrationConfig>(
          "scan_matching.segment_fallback_max_surface_points", 0, rangeClosed(0, 100000),
          "two-point segments only on surfaces of at most this many points (0: any)",
          AT(collector.plicp.line_fit.segment_fallback_max_surface_points)),
      number<CalibrationConfig>("scan_matching.veiling_min_angle_rad", 0.0, "rad",
                                ConfigRange{0.0, M_PI / 2, false, true},
                                "drop veiling points at depth steps seen below this angle (0: off)",
                                AT(collector.plicp.line_fit.veiling_min_angle_rad)),
      number<CalibrationConfig>("scan_matching.trim_keep_fraction", 0.95, "",
                                rangeClosed(0.01, 1.0),
                                "keep at most this fraction of the correspondences (the nearest)",
                                AT(collector.plicp.trim_keep_fraction)),
  };
}

}  // namespace

const std::vector<ConfigSchemaEntry<JointConfig>>& jointConfigSchema()
{
  static const std::vector<JointEntry> entries = jointEntries();
  return entries;
}

const std::vector<ConfigSchemaEntry<EgoMotionSourceConfig>>& sourceConfigSchema()
{
  static const std::vector<SourceEntry> entries = sourceEntries();
  return entries;
}

const std::vector<ConfigSchemaEntry<CalibrationConfig>>& calibrationConfigSchema()
{
  static const std::vector<Entry> entries = [] {
    std::vector<Entry> all;
    for (auto section :
         {topLevelEntries, wheelEntries, egoMotionEntries, cloudScanEntries, cloudFilterEntries,
          keyframeEntries, keyframeListEntries, scanMatchingEntries})
      appendEntries(all, section());
    appendEntries(all, gyroConfigSchema());
    appendEntries(all, modelConfigSchema());
    return all;
  }();
  return entries;
}

std::vector<const ConfigKeySpec*> calibrationConfigSpecs()
{
  std::vector<const ConfigKeySpec*> specs;
  for (const auto& entry : jointConfigSchema())
    specs.push_back(&entry.spec);
  for (const auto& entry : sourceConfigSchema())
    specs.push_back(&entry.spec);
  for (const auto& entry : calibrationConfigSchema())
    specs.push_back(&entry.spec);
  return specs;
}

}  // namespace odometry_calibration