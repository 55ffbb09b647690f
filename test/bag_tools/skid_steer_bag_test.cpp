// Issue 17 acceptance on simulated laser bags (pairs through PLICP, as users get them): a
// skid-steer robot whose lateral slip makes it turn as a diff drive 1.45 times its track width.
// calibrate_bag with config/skid_steer.yaml finds the multiplier within 2 %, writes it to
// controller.yaml, and its --test table carries the nominal row; score_calibration scores the
// saved result on the test bag with the same numbers, without refitting.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"
#include "support/score_table.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test_support::readFile;
using test_support::scoreTableRow;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
constexpr double kTrueMultiplier = 1.45;  // config/sim/scenarios/skid_steer_office.yaml

struct ToolResult
{
  int status = -1;
  std::string out, err;
};

ToolResult run(const std::string& directory, const std::string& command)
{
  const std::string out = directory + "/out.txt", err = directory + "/err.txt";
  const int status = std::system((command + " > " + out + " 2> " + err).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(out), readFile(err)};
}

TEST(SkidSteerBag, MultiplierWithinTwoPercentNominalRowAndScoredAgain)
{
  char pattern[] = "/tmp/skid_steer_bag_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/skid_steer_office.yaml",
                                                 kConfig + "/sim/worlds");
  simulateToBag(scenario, directory + "/train.bag", "");
  scenario.seed = 4;
  scenario.duration_s = 60.0;
  simulateToBag(scenario, directory + "/test.bag", "");
  // The tools' rows are compared at one time offset: the shipped configuration with the offset
  // known (0) rather than estimated (each run's estimate, a fraction of a millisecond, pairs the
  // test bag a hair differently from the pairs file compare_models reads).
  const std::string config = directory + "/skid_steer.yaml";
  std::string shipped = readFile(kConfig + "/skid_steer.yaml");
  const std::size_t keyframes = shipped.find("\nkeyframes:\n");
  ASSERT_NE(keyframes, std::string::npos);
  shipped.insert(keyframes + 12, "  estimate_time_offset: false\n");
  std::ofstream(config) << shipped;

  const ToolResult fit = run(directory, std::string(CALIBRATE_BAG_PROGRAM) + " --config " + config +
                                            " " + directory + "/train.bag --test " + directory +
                                            "/test.bag --quiet --output-dir " + directory + "/out");
  ASSERT_EQ(fit.status, 0) << fit.out << fit.err;
  const YAML::Node controller = YAML::LoadFile(directory + "/out/controller.yaml");
  const double multiplier = controller["wheel_separation_multiplier"].as<double>();
  EXPECT_NEAR(multiplier, kTrueMultiplier, 0.02 * kTrueMultiplier);
  EXPECT_DOUBLE_EQ(controller["wheel_separation"].as<double>(), 0.5);  // the geometric value
  EXPECT_NEAR(controller["left_wheel_radius_multiplier"].as<double>(), 1.0, 0.01);
  EXPECT_NEAR(controller["right_wheel_radius_multiplier"].as<double>(), 1.01, 0.01);
  const YAML::Node result = YAML::LoadFile(directory + "/out/result.yaml");
  EXPECT_NEAR(result["parameters"]["wheel_separation_multiplier"]["value"].as<double>(), multiplier,
              1e-6);
  std::cout << "skid_steer_office: wheel_separation_multiplier " << multiplier << " (truth "
            << kTrueMultiplier << ")\n";

  // The --test table: the fitted model, then the nominal robot (the geometric values), far worse.
  const std::vector<double> fitted = scoreTableRow(fit.out, "skid_steer"),
                            nominal = scoreTableRow(fit.out, "nominal");
  ASSERT_EQ(fitted.size(), 5u) << fit.out;
  ASSERT_EQ(nominal.size(), 5u) << fit.out;
  EXPECT_GT(nominal[4], 3.0 * fitted[4]) << fit.out;  // heading RMSE
  EXPECT_GT(nominal[3], 3.0 * fitted[3]) << fit.out;  // lateral RMSE
  // result.yaml's scores hold the table's rows.
  const YAML::Node test_rows = result["scores"]["test"]["models"];
  ASSERT_EQ(test_rows.size(), 2u);
  EXPECT_EQ(test_rows[0]["model"].as<std::string>(), "skid_steer");
  EXPECT_EQ(test_rows[1]["model"].as<std::string>(), "nominal");
  EXPECT_NEAR(test_rows[0]["rmse_theta_rad"].as<double>(), fitted[4], 1e-5);
  EXPECT_NEAR(test_rows[1]["rmse_theta_rad"].as<double>(), nominal[4], 1e-5);

  // The saved result scored on the same test bag: the same rows, nothing refitted.
  const ToolResult score =
      run(directory, std::string(SCORE_CALIBRATION_PROGRAM) + " --config " + config + " --result " +
                         directory + "/out/result.yaml " + directory + "/test.bag --quiet");
  ASSERT_EQ(score.status, 0) << score.out << score.err;
  const std::vector<double> again = scoreTableRow(score.out, "skid_steer");
  const std::vector<double> nominal_again = scoreTableRow(score.out, "nominal");
  ASSERT_EQ(again.size(), 5u) << score.out;
  ASSERT_EQ(nominal_again.size(), 5u) << score.out;
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(again[i], fitted[i], 1e-5) << i << "\n" << fit.out << score.out;
    EXPECT_NEAR(nominal_again[i], nominal[i], 1e-5) << i;
  }

  // A model this robot's joints cannot serve (linear: the wheels of a side turn together) is
  // skipped with the reason; skid_steer is still fitted, written and scored, gp too (it merges
  // equal inputs).
  std::string config_text = readFile(config);
  const std::size_t compare = config_text.find("compare_models: []");
  ASSERT_NE(compare, std::string::npos);
  config_text.replace(compare, 18, "compare_models: [linear, gp]");
  {
    std::ofstream(directory + "/compare.yaml") << config_text;
  }
  const ToolResult skipping =
      run(directory, std::string(CALIBRATE_BAG_PROGRAM) + " --config " + directory +
                         "/compare.yaml " + directory + "/train.bag --test " + directory +
                         "/test.bag --quiet --output-dir " + directory + "/compare_out");
  EXPECT_TRUE(skipping.status == 0 || skipping.status == 4) << skipping.out << skipping.err;
  EXPECT_TRUE(fs::exists(directory + "/compare_out/controller.yaml"));
  const std::vector<double> still_fitted = scoreTableRow(skipping.out, "skid_steer");
  ASSERT_EQ(still_fitted.size(), 5u) << skipping.out;
  EXPECT_NEAR(still_fitted[4], fitted[4], 1e-9);
  EXPECT_NE(skipping.out.find("skipped: linear (linear model: the encoder increments do not vary "
                              "independently"),
            std::string::npos)
      << skipping.out;
  EXPECT_EQ(scoreTableRow(skipping.out, "gp").size(), 5u) << skipping.out;
  EXPECT_EQ(skipping.out.find("skipped: gp"), std::string::npos) << skipping.out;

  // compare_models with the configuration: skid_steer's sides and the nominal row from it, on
  // calibrate_bag's pairs (training on the first, testing on the second bag's).
  const ToolResult test_pairs =
      run(directory, std::string(CALIBRATE_BAG_PROGRAM) + " --config " + config + " " + directory +
                         "/test.bag --quiet --output-dir " + directory + "/test_out");
  ASSERT_EQ(test_pairs.status, 0) << test_pairs.out << test_pairs.err;
  const ToolResult compared =
      run(directory, std::string(COMPARE_MODELS_PROGRAM) + " --config " + config +
                         " --models skid_steer --train " + directory + "/out/pairs.csv --test " +
                         directory + "/test_out/pairs.csv");
  ASSERT_EQ(compared.status, 0) << compared.out << compared.err;
  const std::vector<double> model_row = scoreTableRow(compared.out, "skid_steer");
  const std::vector<double> nominal_row = scoreTableRow(compared.out, "nominal");
  ASSERT_EQ(model_row.size(), 5u) << compared.out;
  ASSERT_EQ(nominal_row.size(), 5u) << compared.out;
  // The same pairs and the same nominal robot as calibrate_bag --test: the same nominal row.
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(nominal_row[i], nominal[i], 1e-5) << i << "\n" << compared.out;
  EXPECT_GT(nominal_row[4], 3.0 * model_row[4]) << compared.out;
  fs::remove_all(directory);
}

}  // namespace
}  // namespace odometry_calibration
