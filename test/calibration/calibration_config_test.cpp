#include <gtest/gtest.h>

#include "odometry_calibration/calibration/calibration_config.h"

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
  EXPECT_NE(message(joints + "keyframes: {interval_s: -1}\n").find("keyframe_interval_s"),
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
  // Wheels in different units cannot share one diff-drive model.
  EXPECT_NE(message("joints: [{name: l, units_per_turn: 100}, {name: r}]\n").find("units_per_turn"),
            std::string::npos);
}

}  // namespace
}  // namespace odometry_calibration
