#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/config/calibration_config.h"
#include "support/alias_bomb.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

TEST(CalibrationConfig, ShippedConfigParses)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  ASSERT_EQ(config.joints.size(), 2u);
  EXPECT_EQ(config.joints[1].name, "right_wheel");
  EXPECT_EQ(config.models.diff_drive.layout.right_index, 1);
  EXPECT_EQ(config.models.diff_drive.layout.ticks_per_turn, 2000.0);
  EXPECT_DOUBLE_EQ(config.models.diff_drive.initial_T_base_sensor.x(), 0.145);
  EXPECT_DOUBLE_EQ(config.collector.keyframe_interval_s, 0.5);
  const auto channels = encoderChannels(config);
  EXPECT_EQ(channels[0].wrap_period, 4294967296.0);
  EXPECT_EQ(config.models.joints.names.size(), 2u);
  // 50 turns/s of 2000 ticks: the glitch limit in ticks per second.
  EXPECT_DOUBLE_EQ(channels[0].max_rate_per_s, 1e5);
  // The line-fit keys of scan_matching reach the matcher's options.
  const CalibrationConfig tuned = parseCalibrationConfig(
      "joints: [{name: l, units_per_turn: 100}, {name: r, units_per_turn: 100}]\n"
      "scan_matching: {segment_fallback_max_surface_points: 4, veiling_min_angle_rad: 0.17, "
      "trim_keep_fraction: 0.9}\n",
      "c.yaml");
  EXPECT_DOUBLE_EQ(tuned.collector.plicp.trim_keep_fraction, 0.9);
  EXPECT_EQ(tuned.collector.plicp.line_fit.segment_fallback_max_surface_points, 4);
  EXPECT_DOUBLE_EQ(tuned.collector.plicp.line_fit.veiling_min_angle_rad, 0.17);
}

/// The text of the error parsing `text` throws, or "" when it parses.
std::string parseError(const std::string& text)
{
  try {
    parseCalibrationConfig(text, "w.yaml");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(CalibrationConfig, WheelsSectionChoosesTheWheelInput)
{
  // The default: JointState positions, the counters wrapping in the session.
  const CalibrationConfig shipped = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  EXPECT_EQ(shipped.wheels.source, WheelSource::kJointState);
  EXPECT_EQ(wheelInputName(shipped.wheels, shipped.joint_state_topic),
            "JointState on '/joint_states'");
  const std::string joints =
      "joints: [{name: l, units_per_turn: 360, counter_bits: 8}, "
      "{name: r, units_per_turn: 360, counter_bits: 8}]\n";
  const CalibrationConfig ticks = parseCalibrationConfig(
      joints +
          "wheels: {source: ticks, topics: [/makeblock/lwheel, /makeblock/rwheel], "
          "message_type: std_msgs/Int16, max_gap_s: 0.3}\n",
      "w.yaml");
  EXPECT_EQ(ticks.wheels.source, WheelSource::kTicks);
  EXPECT_EQ(ticks.wheels.topics[1], "/makeblock/rwheel");
  EXPECT_DOUBLE_EQ(ticks.wheels.max_gap_s, 0.3);
  EXPECT_EQ(wheelInputName(ticks.wheels, ticks.joint_state_topic),
            "std_msgs/Int16 ticks on '/makeblock/lwheel', '/makeblock/rwheel'");
  // Unwrapped before the session: no channel wraps (the 8-bit counter is unwrapped per topic).
  EXPECT_EQ(encoderChannels(ticks)[0].wrap_period, 0.0);
  const CalibrationConfig velocity =
      parseCalibrationConfig(joints + "wheels: {source: joint_velocity}\n", "w.yaml");
  EXPECT_EQ(velocity.wheels.source, WheelSource::kJointVelocity);
  EXPECT_EQ(encoderChannels(velocity)[1].wrap_period, 0.0);
  EXPECT_EQ(encoderChannels(parseCalibrationConfig(joints, "w.yaml"))[1].wrap_period, 256.0);
}

TEST(CalibrationConfig, WheelsMistakesAreNamed)
{
  const std::string joints =
      "joints: [{name: l, units_per_turn: 360, counter_bits: 32}, "
      "{name: r, units_per_turn: 360}]\n";
  EXPECT_NE(parseError(joints + "wheels: {source: ticks, topics: [/l]}\n")
                .find("wheels.topics: 1 topics for 2 joints"),
            std::string::npos);
  EXPECT_NE(parseError(joints + "wheels: {source: ticks, topics: [/l, /l]}\n")
                .find("'/l' is listed twice"),
            std::string::npos);
  EXPECT_NE(parseError(joints +
                       "wheels: {source: ticks, topics: [/l, /r], message_type: std_msgs/Int16}\n")
                .find("joints[0].counter_bits 32 does not fit std_msgs/Int16 (16 bits)"),
            std::string::npos);
  EXPECT_NE(parseError(joints + "wheels: {topics: [/l, /r]}\n")
                .find("only wheels.source ticks (per-wheel topics) and odometry read topics"),
            std::string::npos);
  EXPECT_NE(parseError(joints + "wheels: {source: odometer}\n").find("wheels.source"),
            std::string::npos);
  EXPECT_NE(parseError(joints + "wheels: {source: ticks, topics: [/l, /r], message_type: Int8}\n")
                .find("wheels.message_type"),
            std::string::npos);
  EXPECT_NE(parseError(joints + "wheels: {source: joint_velocity, max_gap_s: 1e308}\n")
                .find("wheels.max_gap_s"),
            std::string::npos);
}

TEST(CalibrationConfig, GyroOdomHeadingNeedsTheGyro)
{
  const std::string joints =
      "joints: [{name: l, units_per_turn: 360}, {name: r, units_per_turn: 360}]\n";
  EXPECT_NE(parseError(joints + "gyro: {odom_heading: true}\n")
                .find("gyro.odom_heading: true needs the gyro: set gyro.topic"),
            std::string::npos);
  EXPECT_NE(
      parseError(joints + "gyro: {topic: /imu, odom_heading: 1e308}\n").find("gyro.odom_heading"),
      std::string::npos);
  EXPECT_TRUE(parseCalibrationConfig(joints + "gyro: {topic: /imu, odom_heading: true}\n", "test")
                  .gyro.odom_heading);
  EXPECT_FALSE(parseCalibrationConfig(joints + "gyro: {topic: /imu}\n", "test").gyro.odom_heading);
}

TEST(CalibrationConfig, BaseOdometryMakesItsOwnJointsAndNeedsItsModels)
{
  const std::string odometry = "wheels: {source: odometry, topics: [/odom]}\n";
  const CalibrationConfig config =
      parseCalibrationConfig(odometry + "model: base_odometry\n", "odometry.yaml");
  ASSERT_EQ(config.joints.size(), 3u);
  EXPECT_EQ(config.joints[2].name, "base_yaw");
  EXPECT_EQ(config.prior_model, "base_odometry");
  EXPECT_EQ(config.models.base_odometry.layout.yaw_index, 2);
  EXPECT_EQ(wheelInputName(config.wheels, config.joint_state_topic), "base odometry on '/odom'");
  // linear and gp take the increments; prior_model falls back to base_odometry.
  EXPECT_EQ(parseCalibrationConfig(odometry + "model: gp\n", "gp.yaml").prior_model,
            "base_odometry");
  EXPECT_NE(parseError(odometry).find("model: diff_drive needs wheel joints, and wheels.source "
                                      "odometry has none: set model to base_odometry"),
            std::string::npos)
      << parseError(odometry);
  EXPECT_NE(parseError(odometry + "model: base_odometry\ncompare_models: [tricycle]\n")
                .find("compare_models: tricycle needs wheel joints"),
            std::string::npos);
  EXPECT_NE(parseError("joints: [{name: l}, {name: r}]\n" + odometry + "model: base_odometry\n")
                .find("joints: wheels.source odometry makes its own joints"),
            std::string::npos);
  EXPECT_NE(parseError("wheels: {source: odometry}\nmodel: base_odometry\n")
                .find("wheels.topics: wheels.source odometry reads one nav_msgs/Odometry topic"),
            std::string::npos);
  EXPECT_NE(parseError("joints: [{name: l}, {name: r}]\nmodel: base_odometry\n")
                .find("model base_odometry takes a base's own odometry: set wheels.source"),
            std::string::npos);
}

TEST(CalibrationConfig, EgoMotionSourcesListSeveralSensors)
{
  const std::string joints =
      "joints: [{name: l, units_per_turn: 100}, {name: r, units_per_turn: "
      "100}]\nkeyframes: {time_offset_s: -0.02}\n";
  // Today's keys: one source, as before.
  const CalibrationConfig one =
      parseCalibrationConfig(joints + "ego_motion: {scan_topic: /front/scan}\n", "one.yaml");
  EXPECT_TRUE(one.ego_motion_sources.empty());
  const std::vector<EgoMotionSourceConfig> single = egoMotionSources(one);
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].topic, "/front/scan");
  EXPECT_EQ(single[0].type, EgoMotionSource::kScan);
  EXPECT_DOUBLE_EQ(single[0].time_offset_s, -0.02);
  // A list: each source's type, frame and time offset (its own, or the keyframes').
  const CalibrationConfig two = parseCalibrationConfig(
      joints +
          "ego_motion:\n  sources:\n"
          "    - {topic: /scan_front, frame: laser_front}\n"
          "    - {topic: /scan_rear, type: scan, frame: laser_rear, time_offset_s: 0.05,\n"
          "       sensor_pose: [-0.3, 0.0, 3.14159]}\n"
          "    - {topic: /vo, type: odometry}\n",
      "two.yaml");
  const std::vector<EgoMotionSourceConfig> sources = egoMotionSources(two);
  ASSERT_EQ(sources.size(), 3u);
  EXPECT_EQ(sources[1].topic, "/scan_rear");
  EXPECT_EQ(sources[1].frame, "laser_rear");
  EXPECT_DOUBLE_EQ(sources[0].time_offset_s, -0.02);
  EXPECT_DOUBLE_EQ(sources[1].time_offset_s, 0.05);
  EXPECT_EQ(sources[2].type, EgoMotionSource::kOdometry);
  EXPECT_EQ(sources[2].frame, "");
  // Each source as a one-source configuration: its topic, type and time offset.
  const CalibrationConfig rear = configForSource(two, 1);
  EXPECT_TRUE(rear.ego_motion_sources.empty());
  EXPECT_EQ(rear.scan_topic, "/scan_rear");
  EXPECT_DOUBLE_EQ(rear.collector.time_offset_s, 0.05);
  EXPECT_DOUBLE_EQ(rear.models.diff_drive.initial_T_base_sensor.x(), -0.3);
  EXPECT_DOUBLE_EQ(configForSource(two, 0).models.diff_drive.initial_T_base_sensor.x(),
                   two.models.diff_drive.initial_T_base_sensor.x());
  const CalibrationConfig vo = configForSource(two, 2);
  EXPECT_EQ(vo.ego_motion, EgoMotionSource::kOdometry);
  EXPECT_EQ(vo.ego_motion_topic, "/vo");
  EXPECT_DOUBLE_EQ(vo.collector.time_offset_s, -0.02);
  EXPECT_THROW(configForSource(two, 3), std::out_of_range);
  EXPECT_EQ(configForSource(one, 0).scan_topic, "/front/scan");
  // One source listed: the one-source keys say the same (what the node and the bag tool read).
  const CalibrationConfig listed = parseCalibrationConfig(
      joints + "ego_motion:\n  sources: [{topic: /points, type: cloud, time_offset_s: 0.1}]\n",
      "listed.yaml");
  EXPECT_EQ(listed.ego_motion, EgoMotionSource::kCloud);
  EXPECT_EQ(listed.ego_motion_topic, "/points");
  EXPECT_DOUBLE_EQ(listed.collector.time_offset_s, 0.1);
}

TEST(CalibrationConfig, EgoMotionPublisherChosenPerSource)
{
  // Issue 32: the node whose scans are used when two publish the topic.
  const std::string joints = "joints: [{name: l}, {name: r}]\n";
  const CalibrationConfig one = parseCalibrationConfig(
      joints + "ego_motion: {scan_topic: /scan, publisher: /laser_driver}\n", "one.yaml");
  EXPECT_EQ(one.ego_motion_publisher, "/laser_driver");
  EXPECT_EQ(egoMotionSources(one).at(0).publisher, "/laser_driver");
  EXPECT_EQ(configForSource(one, 0).ego_motion_publisher, "/laser_driver");
  EXPECT_EQ(parseCalibrationConfig(joints, "none.yaml").ego_motion_publisher, "");
  // With several sources each has its own; the one-source key beside the list is refused.
  const CalibrationConfig two = parseCalibrationConfig(
      joints +
          "ego_motion:\n  sources:\n    - {topic: /front, publisher: /front_driver}\n"
          "    - {topic: /rear}\n",
      "two.yaml");
  EXPECT_EQ(configForSource(two, 0).ego_motion_publisher, "/front_driver");
  EXPECT_EQ(configForSource(two, 1).ego_motion_publisher, "");
  try {
    parseCalibrationConfig(joints + "ego_motion:\n  publisher: /a\n  sources: [{topic: /front}]\n",
                           "both.yaml");
    FAIL() << "ego_motion.publisher beside ego_motion.sources was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("ego_motion.publisher: give either"),
              std::string::npos)
        << error.what();
  }
}

TEST(CalibrationConfig, EgoMotionSourcesMistakesAreNamed)
{
  const std::string joints = "joints: [{name: l}, {name: r}]\n";
  auto refusal = [&](const std::string& ego_motion) {
    try {
      parseCalibrationConfig(joints + "ego_motion:\n" + ego_motion, "c.yaml");
      return std::string();
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
  };
  EXPECT_NE(refusal("  sources: [{type: scan}]\n").find("ego_motion.sources[0].topic: required"),
            std::string::npos);
  EXPECT_NE(refusal("  sources: [{topic: /a}, {topic: /a}]\n").find("sources[1].topic"),
            std::string::npos);
  EXPECT_NE(refusal("  sources: [{topic: /a, type: sonar}]\n").find("sources[0].type"),
            std::string::npos);
  EXPECT_NE(refusal("  sources: [{topic: /a, colour: red}]\n").find("colour"), std::string::npos);
  EXPECT_NE(refusal("  sources: []\n").find("ego_motion.sources"), std::string::npos);
  EXPECT_NE(refusal("  scan_topic: /s\n  sources: [{topic: /a}]\n").find("ego_motion.scan_topic"),
            std::string::npos);
  EXPECT_NE(refusal("  sources: [{topic: /a, time_offset_s: 7}]\n").find("time_offset_s"),
            std::string::npos);
}

TEST(CalibrationConfig, AbsoluteJointsGetAGlitchLimitToo)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/tricycle.yaml");
  const auto channels = encoderChannels(config);
  bool has_absolute = false;
  for (std::size_t i = 0; i < channels.size(); ++i) {
    if (channels[i].kind != EncoderKind::kAbsolute)
      continue;
    has_absolute = true;
    // A steering angle in radians: max_turns_per_s (default 50) turns of units_per_turn (2 pi).
    EXPECT_DOUBLE_EQ(channels[i].max_rate_per_s,
                     config.joints[i].max_turns_per_s * config.joints[i].units_per_turn)
        << channels[i].name;
    EXPECT_GT(channels[i].max_rate_per_s, 0.0) << channels[i].name;
  }
  EXPECT_TRUE(has_absolute);
}

TEST(CalibrationConfig, SkidSteerConfigResolvesBothSidesAndIsTheNominal)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/skid_steer.yaml");
  EXPECT_EQ(config.model, "skid_steer");
  EXPECT_EQ(config.prior_model, "skid_steer");
  const SkidSteerOptions& s = config.models.skid_steer;
  EXPECT_EQ(s.left_indices, (std::vector<int>{0, 1}));
  EXPECT_EQ(s.right_indices, (std::vector<int>{2, 3}));
  EXPECT_DOUBLE_EQ(s.wheel_separation_m, 0.5);
  EXPECT_DOUBLE_EQ(s.ticks_per_turn, 2000.0);
  EXPECT_DOUBLE_EQ(priorSensorPose(config)->x(), 0.25);
  // The nominal robot: both sides 100 ticks forward = 2 pi 0.1 m / 20 straight ahead; the
  // laser sits on the axis, so it moves as the base does.
  const std::vector<EncoderSample> samples = {{0.0, Eigen::Vector4d(0, 0, 0, 0)},
                                              {0.5, Eigen::Vector4d(90, 110, 100, 100)}};
  const Pose2 motion = priorPredictor(config)(samples);
  EXPECT_NEAR(motion.x(), 2.0 * M_PI * 0.1 / 20.0, 1e-12);
  EXPECT_NEAR(motion.theta(), 0.0, 1e-12);
  ASSERT_TRUE(priorModel(config));
  EXPECT_EQ(priorModel(config)->name(), "skid_steer");

  // Default sides: the incremental joints named *left* / *right*; none to default to: said.
  const std::string four =
      "joints: [{name: fl_left}, {name: rl_left}, {name: fr_right}, {name: rr_right}]\n";
  const CalibrationConfig defaults = parseCalibrationConfig(four + "model: skid_steer\n", "c");
  EXPECT_EQ(defaults.models.skid_steer.left_indices, (std::vector<int>{0, 1}));
  EXPECT_EQ(defaults.models.skid_steer.right_indices, (std::vector<int>{2, 3}));
  try {
    parseCalibrationConfig("joints: [{name: a}, {name: b}]\nmodel: skid_steer\n", "c.yaml");
    FAIL() << "skid_steer without sides was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("skid_steer"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("left_joints"), std::string::npos) << error.what();
  }
  EXPECT_THROW(parseCalibrationConfig(four + "model: skid_steer\nskid_steer: {left_joints: [x]}\n",
                                      "c.yaml"),
               std::runtime_error);
}

TEST(CalibrationConfig, TheLidarTemplateReadsItsCloudOptions)
{
  const CalibrationConfig config = loadCalibrationConfig(
      std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/diff_drive_lidar3d.yaml");
  EXPECT_EQ(config.ego_motion, EgoMotionSource::kCloud);
  EXPECT_TRUE(matchesScans(config.ego_motion));
  EXPECT_EQ(config.ego_motion_topic, "/points");
  EXPECT_EQ(config.cloud.band_min_m, -0.3);
  EXPECT_EQ(config.cloud.band_max_m, 0.3);
  EXPECT_EQ(config.cloud.angular_resolution_rad, 0.00698);
  EXPECT_EQ(config.cloud.range_max_m, 40.0);
  EXPECT_EQ(config.cloud.min_points, 20u);  // scan_matching.min_points
}

TEST(CalibrationConfig, ErrorsNameTheKey)
{
  auto message = [](const std::string& text) -> std::string {
    try {
      parseCalibrationConfig(text, "c.yaml");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  const std::string joints =
      "joints: [{name: l, units_per_turn: 100}, {name: r, units_per_turn: 100}]\n";
  EXPECT_EQ(message(joints), "");
  EXPECT_NE(message("model: linear\n").find("joints"), std::string::npos);
  EXPECT_NE(message(joints + "keyframes: {interval: 0.5}\n").find("unknown key 'interval'"),
            std::string::npos);
  EXPECT_NE(message(joints + "keyframes: {interval_s: -1}\n").find("keyframes.interval_s: -1"),
            std::string::npos);
  EXPECT_NE(message("joints: [{name: l, kind: sideways}]\n").find("joints[0]"), std::string::npos);
  EXPECT_NE(message(joints + "diff_drive: {left_joint: front}\n").find("front"), std::string::npos);
  EXPECT_NE(message(joints + "ego_motion: {source: pose}\n").find("topic"), std::string::npos);
  EXPECT_NE(message(joints + "ego_motion: {source: cloud}\n").find("needs 'topic'"),
            std::string::npos);
  EXPECT_NE(message(joints + "ego_motion: {source: cloud, topic: /p, cloud: {band: 1}}\n")
                .find("ego_motion.cloud: unknown key 'band'"),
            std::string::npos);
  EXPECT_NE(message(joints + "ego_motion: {source: cloud, topic: /p, cloud: {band_m: [1, 0]}}\n")
                .find("band_min_m < band_max_m"),
            std::string::npos);
  EXPECT_NE(message(joints + "model: magic\n").find("magic"), std::string::npos);
  EXPECT_EQ(message(joints + "model: gp\ncompare_models: [linear, diff_drive]\n"), "");
  EXPECT_NE(message(joints + "compare_models: [linear, gpp]\n").find("compare_models"),
            std::string::npos);
  EXPECT_EQ(message(joints + "keyframes: {fit_intervals_s: [0.3, 0.5, 1.0]}\n"), "");
  EXPECT_NE(message(joints + "keyframes: {fit_intervals_s: [0.5, 0.3]}\n").find("must increase"),
            std::string::npos);
  EXPECT_NE(message(joints + "keyframes: {fit_intervals_s: [0, 1]}\n").find("fit_intervals_s"),
            std::string::npos);
  // The consecutive chain's rays: every ray (0) or enough for a match (min_points, 20).
  EXPECT_EQ(message(joints + "keyframes: {consecutive_max_rays: 20}\n"), "");
  EXPECT_NE(message(joints + "keyframes: {consecutive_max_rays: 19}\n")
                .find("keyframes: consecutive_max_rays must be 0 (every ray) or at least "
                      "scan_matching.min_points"),
            std::string::npos)
      << message(joints + "keyframes: {consecutive_max_rays: 19}\n");
  EXPECT_EQ(message(joints + "keyframes: {consecutive_max_rays: 10}\nscan_matching: {min_points: "
                             "10}\n"),
            "");
  EXPECT_NE(message(joints + "scan_matching: {segment_fallback_max_surface_points: -1}\n")
                .find("segment_fallback_max_surface_points"),
            std::string::npos);
  EXPECT_NE(
      message(joints + "scan_matching: {veiling_min_angle_rad: 2}\n").find("veiling_min_angle_rad"),
      std::string::npos);
  EXPECT_NE(
      message(joints + "scan_matching: {trim_keep_fraction: 1.5}\n").find("trim_keep_fraction"),
      std::string::npos);
  // Wheels in different units cannot share one diff-drive model.
  EXPECT_NE(message("joints: [{name: l, units_per_turn: 100}, {name: r}]\n").find("units_per_turn"),
            std::string::npos);
}

TEST(CalibrationConfig, MecanumTemplateParsesAndNamesItsWheels)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/mecanum.yaml");
  EXPECT_EQ(config.model, "mecanum");
  EXPECT_EQ(config.prior_model, "mecanum");
  const MecanumOptions& m = config.models.mecanum;
  EXPECT_EQ(m.layout.rear_right_index, 3);
  EXPECT_EQ(m.layout.ticks_per_turn, 1000.0);
  EXPECT_DOUBLE_EQ(m.initial_lx_plus_ly_m, 0.35);
  EXPECT_DOUBLE_EQ(priorSensorPose(config)->x(), 0.2);
  // The nominal model drives the matcher's guesses: 1000 ticks on every wheel is one wheel
  // turn forward, 2 pi r.
  const MotionPredictor guess = priorPredictor(config);
  ASSERT_TRUE(guess);
  EncoderSample a, b;
  a.values = Eigen::Vector4d::Zero();
  b.values = Eigen::Vector4d::Constant(1000.0);
  EXPECT_NEAR(guess({a, b}).x(), 2 * M_PI * 0.05, 1e-12);
  EXPECT_EQ(priorModel(config)->name(), "mecanum");

  // Joints by name in another order; errors name the key.
  auto message = [](const std::string& text) -> std::string {
    try {
      parseCalibrationConfig(text, "m.yaml");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  const std::string joints = "joints: [{name: rr}, {name: fl}, {name: fr}, {name: rl}]\n";
  const CalibrationConfig named = parseCalibrationConfig(
      joints +
          "model: mecanum\nmecanum: {front_left_joint: fl, front_right_joint: fr, "
          "rear_left_joint: rl, rear_right_joint: rr, wheel_radii_m: [0.05, 0.05, 0.051, 0.05]}\n",
      "m.yaml");
  EXPECT_EQ(named.models.mecanum.layout.front_left_index, 1);
  EXPECT_EQ(named.models.mecanum.layout.rear_right_index, 0);
  EXPECT_DOUBLE_EQ(named.models.mecanum.initial_radius_m[2], 0.051);
  EXPECT_NE(message(joints + "model: mecanum\nmecanum: {rear_left_joint: back}\n")
                .find("mecanum.rear_left_joint"),
            std::string::npos);
  EXPECT_NE(
      message(joints + "model: mecanum\nmecanum: {wheel_radii_m: [0.05]}\n").find("wheel_radii_m"),
      std::string::npos);
  EXPECT_NE(message("joints: [{name: a}, {name: b}]\nmodel: mecanum\n").find("four wheel"),
            std::string::npos);
  EXPECT_NE(message(joints + "model: mecanum\nmecanum: {lx_plus_ly_m: 0}\n").find("lx_plus_ly"),
            std::string::npos);
  // A gp fitted on a mecanum robot may take the mecanum model as its nominal one.
  EXPECT_EQ(message(joints + "model: gp\nprior_model: mecanum\n"), "");
}

}  // namespace
}  // namespace odometry_calibration

namespace odometry_calibration {
namespace {

/// The message loading `path` throws ("" when it loads).
std::string loadRefusal(const std::string& path)
{
  try {
    loadCalibrationConfig(path);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(CalibrationConfig, AnAliasBombIsRefusedAtOnceNamingTheFile)
{
  // Nine levels of ten aliases each: 10^9 nodes once expanded, which every walk of the
  // document (duplicate keys, unknown keys) expanded for minutes.
  const std::string text = test::aliasBomb(9, "joints: [{name: l}, {name: r}]\n");
  char pattern[] = "/tmp/calibration_config_test.XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::string path = std::string(pattern) + "/bomb.yaml";
  std::ofstream(path) << text;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = loadRefusal(path);
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(message.rfind(path + ": YAML aliases expand to more than 100000 nodes", 0), 0u)
      << message;
  EXPECT_LT(elapsed_s, 2.0);
  // The ~calibrate options are read with the same bound.
  std::string options_message;
  try {
    configForModel("joints: [{name: l}, {name: r}]\n", "diff_drive", text, "c.yaml");
  } catch (const std::runtime_error& error) {
    options_message = error.what();
  }
  EXPECT_NE(options_message.find("options: YAML aliases expand to more than 100000 nodes"),
            std::string::npos)
      << options_message;
  std::filesystem::remove_all(pattern);
}

TEST(CalibrationConfig, APathThatIsNoConfigurationSaysWhatItIs)
{
  char pattern[] = "/tmp/calibration_config_test.XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::string directory = pattern;
  EXPECT_EQ(loadRefusal(directory), directory + " is a directory, not a configuration file");
  EXPECT_EQ(loadRefusal(directory + "/none.yaml"),
            directory + "/none.yaml does not exist: give the path of the configuration file");
  std::ofstream(directory + "/empty.yaml").close();
  EXPECT_EQ(loadRefusal(directory + "/empty.yaml"),
            directory + "/empty.yaml is empty: the configuration file holds nothing to read");
  std::ofstream(directory + "/comments.yaml") << "# joints: to do\n\n";
  EXPECT_EQ(loadRefusal(directory + "/comments.yaml"),
            directory +
                "/comments.yaml holds no settings (only blanks or comments): a configuration "
                "needs at least its joints (see config/diff_drive.yaml)");
  std::filesystem::remove_all(directory);
}

}  // namespace
}  // namespace odometry_calibration
