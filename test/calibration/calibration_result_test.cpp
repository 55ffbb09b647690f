#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

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

/// The blocks a tool appends (the interval's choice, the scores) keep every number, an
/// unscorable candidate as .inf and a skipped row with its reason, and the file still loads.
TEST(CalibrationResult, AppendedBlocksCarryTheChoiceAndTheScores)
{
  const sim::GeneratedPairs data = simulatedPairs();
  auto model = makeModel("diff_drive", factoryOptions(data.joints));
  const ModelReport report = model->fit(data.pairs);
  FitIntervalChoice choice;
  choice.interval_s = 0.5;
  choice.criterion = FitIntervalCriterion::kAte;
  choice.fold_counts = {3, 4};
  choice.curve = {{0.3, 0.0123, 290, 7}, {0.5, 0.0101, 180, 7}, {8.0, INFINITY, 11, 0}};
  ModelScore fitted;
  fitted.model = "diff_drive";
  fitted.ate_m = 0.0456;
  fitted.rpe_m = 0.00789;
  fitted.rmse_xytheta = Eigen::Vector3d(0.001, 0.002, 0.003);
  fitted.test_pairs = 42;
  ModelScore skipped;
  skipped.model = "linear";
  skipped.skipped = "too few pairs";
  const std::string text =
      calibrationResultYaml(report, *model, "test", 0.0, {}, 0.5) +
      fitIntervalChoiceYaml(choice, 0.25) +
      scoresYaml({{"held_out", "the last 40 %", {fitted, skipped}}, {"test", "bags", {fitted}}});
  EXPECT_EQ(scoresYaml({}), "");

  const YAML::Node root = YAML::Load(text);
  const YAML::Node block = root["fit_interval_choice"];
  EXPECT_EQ(block["criterion"].as<std::string>(), "ATE");
  EXPECT_DOUBLE_EQ(block["evaluation_interval_s"].as<double>(), 0.25);
  EXPECT_EQ(block["fold_counts"].as<std::vector<std::size_t>>(), (std::vector<std::size_t>{3, 4}));
  ASSERT_EQ(block["curve"].size(), 3u);
  EXPECT_DOUBLE_EQ(block["curve"][1]["validation_error_m"].as<double>(), 0.0101);
  EXPECT_EQ(block["curve"][1]["pairs"].as<std::size_t>(), 180u);
  EXPECT_TRUE(std::isinf(block["curve"][2]["validation_error_m"].as<double>()));
  const YAML::Node held_out = root["scores"]["held_out"];
  EXPECT_EQ(held_out["description"].as<std::string>(), "the last 40 %");
  ASSERT_EQ(held_out["models"].size(), 2u);
  const YAML::Node row = held_out["models"][0];
  EXPECT_EQ(row["model"].as<std::string>(), "diff_drive");
  EXPECT_EQ(row["pairs"].as<std::size_t>(), 42u);
  EXPECT_DOUBLE_EQ(row["ate_m"].as<double>(), 0.0456);
  EXPECT_DOUBLE_EQ(row["rpe_m"].as<double>(), 0.00789);
  EXPECT_DOUBLE_EQ(row["rmse_theta_rad"].as<double>(), 0.003);
  EXPECT_EQ(held_out["models"][1]["skipped"].as<std::string>(), "too few pairs");
  EXPECT_FALSE(held_out["models"][1]["ate_m"]);
  EXPECT_EQ(root["scores"]["test"]["models"].size(), 1u);
  EXPECT_DOUBLE_EQ(parseCalibrationResult(text, "result.yaml").fit_interval_s, 0.5);
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
