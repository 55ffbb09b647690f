#include "odometry_calibration/eval/model_comparison.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

sim::GeneratedPairs pairs(unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.duration_s = 60.0;
  options.seed = seed;
  return sim::generatePairs(options);
}

TEST(ModelComparison, FitsEachModelOnTrainingAndScoresItOnTest)
{
  const sim::GeneratedPairs training = pairs(1), testing = pairs(2);
  ModelFactoryOptions options;
  options.joints = training.joints;
  options.diff_drive.initial_left_radius_m = 0.077;
  options.diff_drive.initial_right_radius_m = 0.077;
  options.diff_drive.initial_separation_m = 0.33;
  const std::vector<ModelScore> scores =
      compareModels({"diff_drive", "linear"}, options, training.pairs, testing.pairs);
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(scores[0].model, "diff_drive");
  EXPECT_EQ(scores[1].model, "linear");
  for (const ModelScore& score : scores) {
    EXPECT_EQ(score.test_pairs, testing.pairs.size());
    EXPECT_GT(score.fit_time_s, 0.0);
    EXPECT_LT(score.ate_m, 1.0);
  }
  // The true model family fits the ideal robot better than a straight line.
  EXPECT_LT(scores[0].rmse_xytheta.norm(), 0.01);
}

TEST(ModelComparison, NeedsTrainingPairsAndKnownModels)
{
  const sim::GeneratedPairs testing = pairs(2);
  ModelFactoryOptions options;
  options.joints = testing.joints;
  try {
    compareModels({"linear"}, options, {}, testing.pairs);
    FAIL() << "no training pair was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "the training files hold no pair");
  }
  EXPECT_THROW(compareModels({"cubic"}, options, testing.pairs, testing.pairs),
               std::invalid_argument);
  EXPECT_TRUE(compareModels({}, options, testing.pairs, testing.pairs).empty());
}

TEST(ModelComparison, MarksAFitThatDidNotConvergeAndLeavesTheOthersAlone)
{
  const sim::GeneratedPairs training = pairs(1), testing = pairs(2);
  ModelFactoryOptions options;
  options.joints = training.joints;
  options.diff_drive.max_iterations = 1;
  options.diff_drive.yaw_starts = 1;
  const std::vector<ModelScore> scores =
      compareModels({"diff_drive", "linear"}, options, training.pairs, testing.pairs);
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_FALSE(scores[0].converged);
  EXPECT_TRUE(scores[1].converged);
  const std::string table = formatComparisonTable(scores);
  const std::string diff_row = table.substr(table.find("\ndiff_drive") + 1);
  EXPECT_NE(diff_row.substr(0, diff_row.find('\n')).find("NOT converged"), std::string::npos);
  const std::string linear_row = table.substr(table.find("\nlinear") + 1);
  EXPECT_EQ(linear_row.substr(0, linear_row.find('\n')).find("NOT converged"), std::string::npos);
  EXPECT_NE(table.find("NOT converged: diff_drive ("), std::string::npos);
}

TEST(ModelComparison, AddsTheUnfittedNominalRowLast)
{
  const sim::GeneratedPairs training = pairs(1), testing = pairs(2);
  ModelFactoryOptions options;
  options.joints = training.joints;
  options.diff_drive.initial_left_radius_m = 0.077;
  options.diff_drive.initial_right_radius_m = 0.077;
  options.diff_drive.initial_separation_m = 0.33;
  options.diff_drive.initial_T_base_sensor = Pose2(0.15, 0.0, 0.0);  // the true sensor pose
  const DiffDriveModel nominal(options.diff_drive);
  const std::vector<ModelScore> scores =
      compareModels({"diff_drive"}, options, training.pairs, testing.pairs, &nominal);
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(scores[1].model, "nominal");
  EXPECT_FALSE(scores[1].fitted);
  EXPECT_EQ(scores[1].test_pairs, testing.pairs.size());
  // The nominal row is the start values' prediction, exactly: scoreModel of the same model.
  const ModelScore direct = scoreModel(nominal, testing.pairs);
  EXPECT_DOUBLE_EQ(scores[1].ate_m, direct.ate_m);
  EXPECT_DOUBLE_EQ(scores[1].rmse_xytheta(2), direct.rmse_xytheta(2));
  // 3 % too wide a separation and 1 % off radii: per pair (0.3 s) the heading error stands
  // above the 2 mrad noise the fit reaches, and chained over the test drive it is far worse.
  EXPECT_GT(scores[1].rmse_xytheta(2), 2.0 * scores[0].rmse_xytheta(2));
  EXPECT_GT(scores[1].ate_m, 3.0 * scores[0].ate_m);
  // Its fit time and outliers show "-", and the table says what the row is.
  const std::string table = formatComparisonTable(scores);
  const std::string row = table.substr(table.find("\nnominal") + 1);
  EXPECT_NE(row.substr(0, row.find('\n')).find(" - "), std::string::npos) << table;
  EXPECT_NE(table.find("nominal: the configured nominal model, not fitted (diff_drive at its "
                       "start values)"),
            std::string::npos)
      << table;
}

TEST(ModelComparison, NamesTheBestRowAndHowManyTimesLowerItsAteIs)
{
  auto row = [](const std::string& name, double ate, double rpe = 0.0) {
    ModelScore score;
    score.model = name;
    score.ate_m = ate;
    score.rpe_m = rpe;
    return score;
  };
  ModelScore skipped = row("tricycle", 0.0);
  skipped.skipped = "two wheels";
  ModelScore stalled = row("mecanum", 0.001);
  stalled.converged = false;
  const std::vector<ModelScore> scores = {row("diff_drive", 0.04, 0.002),
                                          row("linear", 0.02, 0.003),
                                          row("gp", 0.01, 0.001),
                                          skipped,
                                          stalled,
                                          row("nominal", 0.2, 0.02)};
  EXPECT_EQ(rankByAte(scores), (std::vector<std::string>{"gp", "linear", "diff_drive", "nominal"}));
  EXPECT_EQ(formatBestModel(scores, "the held-out pairs"),
            "best on the held-out pairs: gp, ATE 0.0100 m, 2.0x lower than linear (0.0200 m), "
            "20.0x lower than nominal (0.2000 m); ranking by ATE: gp < linear < diff_drive < "
            "nominal, by RPE: gp < diff_drive < linear < nominal\n");
  EXPECT_EQ(rankByRpe(scores), (std::vector<std::string>{"gp", "diff_drive", "linear", "nominal"}));
  EXPECT_EQ(formatBestModel({row("gp", 0.01)}, "x"), "");
}

}  // namespace
}  // namespace odometry_calibration
