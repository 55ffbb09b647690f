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
  // Wheels in different units cannot share one diff-drive model.
  EXPECT_NE(message("joints: [{name: l, units_per_turn: 100}, {name: r}]\n").find("units_per_turn"),
            std::string::npos);
}

}  // namespace
}  // namespace odometry_calibration
