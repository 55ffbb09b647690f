#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/sim/pair_generator.h"
#include "support/alias_bomb.h"

namespace odometry_calibration {
namespace {

sim::GeneratedPairs simulatedPairs()
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  options.duration_s = 90.0;
  options.interval_s = 0.5;
  return sim::generatePairs(options);
}

ModelFactoryOptions factoryOptions(const JointLayout& joints)
{
  ModelFactoryOptions options;
  options.joints = joints;
  options.diff_drive.initial_left_radius_m = 0.077;
  options.diff_drive.initial_right_radius_m = 0.077;
  options.diff_drive.initial_separation_m = 0.33;
  options.diff_drive.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return options;
}

/// Saving and loading a fitted model of each kind predicts the same motions, and keeps the
/// extrinsic and the time offset.
TEST(CalibrationResult, RoundTripPredictsIdentically)
{
  const sim::GeneratedPairs data = simulatedPairs();
  for (const std::string name : {"diff_drive", "linear", "gp"}) {
    SCOPED_TRACE(name);
    auto model = makeModel(name, factoryOptions(data.joints));
    const ModelReport report = model->fit(data.pairs);
    const std::string text = calibrationResultYaml(report, *model, "test", -0.125, {}, 0.3);
    const CalibrationResult loaded = parseCalibrationResult(text, "result.yaml");
    ASSERT_TRUE(loaded.model);
    EXPECT_DOUBLE_EQ(loaded.fit_interval_s, 0.3);
    // Written without an interval (results before issue 22): not recorded.
    EXPECT_EQ(parseCalibrationResult(calibrationResultYaml(report, *model, "test", 0.0), "old")
                  .fit_interval_s,
              0.0);
    EXPECT_EQ(loaded.model->name(), name);
    EXPECT_EQ(loaded.has_extrinsic, report.has_extrinsic);
    EXPECT_DOUBLE_EQ(loaded.time_offset_s, -0.125);
    if (report.has_extrinsic) {
      EXPECT_NEAR(loaded.T_base_sensor.x(), report.T_base_sensor.x(), 1e-9);
      EXPECT_NEAR(loaded.T_base_sensor.theta(), report.T_base_sensor.theta(), 1e-9);
      EXPECT_NEAR(loaded.T_base_sensor.x(), 0.145, 0.01);  // the fit itself is right
    }
    for (std::size_t i = 0; i < data.pairs.size(); i += 17) {
      const Pose2 a = model->predict(data.pairs[i].encoder_samples).mean;
      const Pose2 b = loaded.model->predict(data.pairs[i].encoder_samples).mean;
      EXPECT_NEAR(a.x(), b.x(), 1e-9);
      EXPECT_NEAR(a.y(), b.y(), 1e-9);
      EXPECT_NEAR(a.theta(), b.theta(), 1e-9);
    }
  }
}

TEST(CalibrationResult, BadFilesNameTheProblem)
{
  try {
    parseCalibrationResult("fit: {converged: true}\n", "old.yaml");
    FAIL() << "no model section accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("old.yaml: no 'model' section"), std::string::npos);
  }
  try {
    parseCalibrationResult("model: {model: unicycle}\n", "r.yaml");
    FAIL() << "unknown model accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("unicycle"), std::string::npos);
  }
  EXPECT_THROW(parseCalibrationResult("model: [unclosed\n", "r.yaml"), std::runtime_error);
  try {
    parseCalibrationResult("model: {model: linear}\nfit_interval_s: -1\n", "r.yaml");
    FAIL() << "a negative fit interval accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("r.yaml: fit_interval_s must be in (0, 3600] s"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(readCalibrationResult("/nonexistent/result.yaml"), std::runtime_error);
  // An alias bomb in a result file is refused before anything walks it.
  try {
    parseCalibrationResult(test::aliasBomb(9, "model: {model: linear}\n"), "bomb.yaml");
    FAIL() << "an alias bomb accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("bomb.yaml: YAML aliases expand to more than 100000"),
              std::string::npos)
        << error.what();
  }
}

TEST(CalibrationResult, AModelForOtherJointsRefusesToPredict)
{
  // Found by fuzz_calibration_result: a result.yaml whose model names joints the samples do
  // not have (another robot's file) read past the samples' values.
  const sim::GeneratedPairs data = simulatedPairs();
  const std::vector<EncoderSample> one_joint = {{0.0, Eigen::VectorXd::Zero(1)},
                                                {0.5, Eigen::VectorXd::Ones(1)}};
  for (const std::string name : {"diff_drive", "linear", "gp"}) {
    SCOPED_TRACE(name);
    auto model = makeModel(name, factoryOptions(data.joints));
    const ModelReport report = model->fit(data.pairs);
    const CalibrationResult loaded =
        parseCalibrationResult(calibrationResultYaml(report, *model, "test", 0.0), "result.yaml");
    EXPECT_THROW(loaded.model->predict(one_joint), std::invalid_argument);
  }
  // A linear model's weight covariance needs one entry per axis (predict reads three).
  const std::string linear_yaml =
      "model: {model: linear, joints: [[left_wheel, incremental], [right_wheel, incremental]], "
      "weights: [[1, 0], [0, 0], [0, 1]], residual_variance: [1, 1, 1], "
      "weight_covariance: [[1, 0, 0, 1]]}\n";
  EXPECT_THROW(parseCalibrationResult(linear_yaml, "result.yaml"), std::runtime_error);
}

TEST(CalibrationResult, UrdfSnippetPlacesTheLaser)
{
  const std::string urdf = laserJointUrdf(Pose2(0.145, -0.02, 0.0314), "base_link", "laser");
  EXPECT_NE(urdf.find("<parent link=\"base_link\"/>"), std::string::npos);
  EXPECT_NE(urdf.find("<child link=\"laser\"/>"), std::string::npos);
  EXPECT_NE(urdf.find("xyz=\"0.145000 -0.020000 0\" rpy=\"0 0 0.031400\""), std::string::npos);
}

TEST(ConfigOverride, ReplacesModelSectionsKeyByKeyAndRefusesOthers)
{
  const std::string config =
      "joints:\n  - {name: l, units_per_turn: 2000}\n  - {name: r, units_per_turn: 2000}\n"
      "diff_drive: {wheel_radius_m: 0.077, wheel_separation_m: 0.33}\n"
      "gp: {kernel: rbf}\n";
  const CalibrationConfig changed = overrideModelOptions(
      config, "{diff_drive: {wheel_radius_m: 0.08}, gp: {kernel: linear}}", "test.yaml");
  EXPECT_DOUBLE_EQ(changed.models.diff_drive.initial_left_radius_m, 0.08);
  EXPECT_DOUBLE_EQ(changed.models.diff_drive.initial_separation_m, 0.33);  // kept
  EXPECT_NE(changed.models.gp.kernel, parseCalibrationConfig(config, "c").models.gp.kernel);
  EXPECT_THROW(overrideModelOptions(config, "{joints: []}", "test.yaml"), std::runtime_error);
  EXPECT_THROW(overrideModelOptions(config, "[1, 2]", "test.yaml"), std::runtime_error);
  EXPECT_THROW(overrideModelOptions(config, "{gp: {kernel: cubic}}", "test.yaml"),
               std::runtime_error);
  EXPECT_DOUBLE_EQ(overrideModelOptions(config, "", "t").models.diff_drive.initial_left_radius_m,
                   0.077);
  // Asking for another model resolves its joints: the wheels cannot be a tricycle's.
  EXPECT_EQ(configForModel(config, "gp", "", "t").model, "gp");
  try {
    configForModel(config, "tricycle", "", "test.yaml");
    FAIL() << "two wheels accepted as a tricycle";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("steering joint must be kind: absolute"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace odometry_calibration
