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
  // 50 turns/s of 2000 ticks: the glitch limit in ticks per second.
  EXPECT_DOUBLE_EQ(channels[0].max_rate_per_s, 1e5);
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
  EXPECT_NE(message(joints + "model: magic\n").find("magic"), std::string::npos);
  EXPECT_EQ(message(joints + "model: gp\ncompare_models: [linear, diff_drive]\n"), "");
  EXPECT_NE(message(joints + "compare_models: [linear, gpp]\n").find("compare_models"),
            std::string::npos);
  EXPECT_EQ(message(joints + "keyframes: {fit_intervals_s: [0.3, 0.5, 1.0]}\n"), "");
  EXPECT_NE(message(joints + "keyframes: {fit_intervals_s: [0.5, 0.3]}\n").find("must increase"),
            std::string::npos);
  EXPECT_NE(message(joints + "keyframes: {fit_intervals_s: [0, 1]}\n").find("fit_intervals_s"),
            std::string::npos);
  // Wheels in different units cannot share one diff-drive model.
  EXPECT_NE(message("joints: [{name: l, units_per_turn: 100}, {name: r}]\n").find("units_per_turn"),
            std::string::npos);
}

}  // namespace
}  // namespace odometry_calibration
