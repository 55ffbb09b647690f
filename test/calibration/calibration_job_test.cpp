// The calibration job shared by the node and calibrate_bag: fit, time offset, comparison.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

constexpr double kLeftRadiusM = 0.0765, kRightRadiusM = 0.0775, kSeparationM = 0.32;

sim::GeneratedPairs simulatedPairs()
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", kLeftRadiusM},
                    {"wheel_radius_right_m", kRightRadiusM},
                    {"wheel_separation_m", kSeparationM}}};
  options.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  options.duration_s = 90.0;
  options.interval_s = 0.5;
  return sim::generatePairs(options);
}

/// Every encoder sample of the pairs once, in time order: the history the pairs were cut from.
std::vector<EncoderSample> encoderHistory(const std::vector<MotionPair>& pairs)
{
  std::map<double, EncoderSample> by_stamp;
  for (const MotionPair& pair : pairs) {
    for (const EncoderSample& sample : pair.encoder_samples)
      by_stamp.emplace(sample.stamp_s, sample);
  }
  std::vector<EncoderSample> history;
  for (const auto& entry : by_stamp)
    history.push_back(entry.second);
  return history;
}

CalibrationConfig diffDriveConfig(const JointLayout& joints)
{
  CalibrationConfig config;
  config.estimate_time_offset = false;  // the tests that estimate it say so
  config.model = "diff_drive";
  config.prior_model = "diff_drive";
  config.models.joints = joints;
  config.models.diff_drive.initial_left_radius_m = 0.077;
  config.models.diff_drive.initial_right_radius_m = 0.077;
  config.models.diff_drive.initial_separation_m = 0.33;
  config.models.diff_drive.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  config.models.linear.joints = joints;
  return config;
}

double parameter(const ModelReport& report, const std::string& name)
{
  for (const ParameterEstimate& estimate : report.parameters) {
    if (estimate.name == name)
      return estimate.value;
  }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

TEST(CalibrationJob, FitsTheConfiguredModelAndComparesWithTheNominalRobot)
{
  const sim::GeneratedPairs data = simulatedPairs();
  const CalibrationConfig config = diffDriveConfig(data.joints);
  const CalibrationJobResult job =
      runCalibrationJob(config, data.pairs, encoderHistory(data.pairs));
  ASSERT_TRUE(job.model);
  EXPECT_EQ(job.model->name(), "diff_drive");
  EXPECT_TRUE(job.report.converged);
  EXPECT_NEAR(parameter(job.report, "left_wheel_radius"), kLeftRadiusM, 0.001);
  EXPECT_NEAR(parameter(job.report, "wheel_separation"), kSeparationM, 0.004);
  EXPECT_FALSE(job.time_offset);  // not asked for
  EXPECT_DOUBLE_EQ(job.time_offset_s, config.collector.time_offset_s);
  EXPECT_EQ(job.pairs.size(), data.pairs.size());
  // The nominal robot (radii 0.077, separation 0.33) is worse than the calibrated one.
  ASSERT_FALSE(job.nominal_description.empty());
  ASSERT_EQ(job.trajectories.nominal_errors.size(), data.pairs.size());
  const std::string line = formatNominalComparison(job);
  double nominal_m = 0, calibrated_m = 0;
  ASSERT_EQ(std::sscanf(line.c_str() + line.find("time offset) ") + 13, "%lf m -> calibrated %lf",
                        &nominal_m, &calibrated_m),
            2)
      << line;
  EXPECT_GT(nominal_m, 3.0 * calibrated_m) << line;
  EXPECT_LT(calibrated_m, 0.005) << line;
}

TEST(CalibrationJob, WithoutTrajectoriesOrHistoryThereIsNoNominalLine)
{
  const sim::GeneratedPairs data = simulatedPairs();
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult job =
      runCalibrationJob(diffDriveConfig(data.joints), data.pairs, {}, options);
  EXPECT_TRUE(job.trajectories.calibrated_errors.empty());
  EXPECT_EQ(formatNominalComparison(job), "");
}

TEST(CalibrationJob, ACutAtAnotherOffsetKeepsThePairsTheEncodersDoNotCover)
{
  // Cut 0.1 s late, the last pair's window runs past the last encoder reading: a search
  // leaves it out, a fit keeps it as it was made.
  const sim::GeneratedPairs data = simulatedPairs();
  const std::vector<EncoderSample> history = encoderHistory(data.pairs);
  const std::vector<MotionPair> left_out = rewindowPairs(data.pairs, history, 0.1);
  const std::vector<MotionPair> kept = rewindowPairs(
      data.pairs, history, 0.1, EncoderInterpolation::kCubic, UncoveredPairs::kKeptAsMade);
  ASSERT_EQ(kept.size(), data.pairs.size());
  ASSERT_LT(left_out.size(), data.pairs.size());
  const MotionPair& last = kept.back();
  ASSERT_EQ(last.encoder_samples.size(), data.pairs.back().encoder_samples.size());
  EXPECT_EQ(last.encoder_samples.front().stamp_s,
            data.pairs.back().encoder_samples.front().stamp_s);
  EXPECT_NE(kept.front().encoder_samples.front().stamp_s,
            data.pairs.front().encoder_samples.front().stamp_s);  // the others are cut again
}

TEST(CalibrationJob, EstimatesTheTimeOffsetAndFitsThePairsCutThere)
{
  const sim::GeneratedPairs data = simulatedPairs();
  const std::vector<EncoderSample> history = encoderHistory(data.pairs);
  CalibrationConfig config = diffDriveConfig(data.joints);
  // Collected with a wrong offset: the encoder windows 0.1 s late against the true 0.
  config.collector.time_offset_s = 0.1;
  config.estimate_time_offset = true;
  config.time_offset_search_min_s = -0.2;
  config.time_offset_search_max_s = 0.2;
  const std::vector<MotionPair> late = rewindowPairs(data.pairs, history, 0.1);
  const CalibrationJobResult job = runCalibrationJob(config, late, history);
  ASSERT_TRUE(job.time_offset);
  EXPECT_NEAR(job.time_offset_s, 0.0, 0.01);
  EXPECT_NEAR(job.time_offset->offset_s, job.time_offset_s, 1e-12);
  EXPECT_NEAR(parameter(job.report, "wheel_separation"), kSeparationM, 0.004);
  EXPECT_NE(formatTimeOffset(*job.time_offset).find("tau = "), std::string::npos);

  // Without a history the search cannot run, and says why.
  try {
    runCalibrationJob(config, late, {});
    FAIL() << "time offset estimated without an encoder history";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("continuous encoder stream"), std::string::npos);
  }
  // The node's job leaves the offset alone.
  CalibrationJobOptions node;
  node.allow_time_offset = false;
  const CalibrationJobResult kept = runCalibrationJob(config, late, {}, node);
  EXPECT_DOUBLE_EQ(kept.time_offset_s, 0.1);
  EXPECT_FALSE(kept.time_offset);
}

TEST(CalibrationJob, ASearchAlreadyDoneIsUsedInsteadOfSearchingAgain)
{
  const sim::GeneratedPairs data = simulatedPairs();
  const std::vector<EncoderSample> history = encoderHistory(data.pairs);
  CalibrationConfig config = diffDriveConfig(data.joints);
  config.estimate_time_offset = true;
  config.time_offset_search_min_s = -0.2;
  config.time_offset_search_max_s = 0.2;
  // A search result (as runBagsAtEstimatedOffset hands on) that is not the data's own
  // minimum (0): the job takes it as it is, cuts the windows there and reports it.
  TimeOffsetResult given;
  given.offset_s = 0.06;
  given.sigma_s = 0.001;
  given.curve = {{0.04, 2.0}, {0.06, 1.0}, {0.08, 2.0}};
  CalibrationJobOptions options;
  options.time_offset_search = given;
  const CalibrationJobResult job = runCalibrationJob(config, data.pairs, history, options);
  ASSERT_TRUE(job.time_offset);
  EXPECT_DOUBLE_EQ(job.time_offset_s, 0.06);
  EXPECT_EQ(job.time_offset->curve.size(), 3u);
  ASSERT_GE(job.pairs.size() + 1, data.pairs.size());  // the history ends before the last one's
  EXPECT_NEAR(job.pairs.front().encoder_samples.front().stamp_s,
              data.pairs.front().start_stamp_s + 0.06, 1e-9);
  // Without it the job searches and finds the data's offset.
  EXPECT_NEAR(runCalibrationJob(config, data.pairs, history).time_offset_s, 0.0, 0.01);
}

TEST(CalibrationJob, ScoresTheModelFirstThenTheComparedOnesThenTheNominal)
{
  const sim::GeneratedPairs data = simulatedPairs();
  CalibrationConfig config = diffDriveConfig(data.joints);
  config.compare_models = {"linear", "diff_drive"};  // the fitted model is not scored twice
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult job = runCalibrationJob(config, data.pairs, {}, options);
  const std::vector<MotionPair> test(data.pairs.begin(), data.pairs.begin() + 60);
  const std::vector<ModelScore> scores = scoreModelsOnTest(config, job, test);
  ASSERT_EQ(scores.size(), 3u);
  EXPECT_EQ(scores[0].model, "diff_drive");
  EXPECT_EQ(scores[1].model, "linear");
  EXPECT_EQ(scores[2].model, "nominal");
  EXPECT_TRUE(scores[0].fitted);
  EXPECT_FALSE(scores[2].fitted);
  EXPECT_EQ(scores[0].test_pairs, 60u);
  EXPECT_EQ(scores[2].test_pairs, 60u);
  // The right parametric model beats the linear one on its own robot...
  EXPECT_LT(scores[0].ate_m, scores[1].ate_m);
  // ...and the nominal robot (radii 0.077 m for 0.0765 / 0.0775, separation 0.33 m for 0.32,
  // sensor 5 cm off) is far worse than the fit: the sensor offset alone errs ~5 cm * turn.
  EXPECT_GT(scores[2].rmse_xytheta(1), 3.0 * scores[0].rmse_xytheta(1));
  // The nominal row shows no fit time or outliers.
  const std::string table = formatComparisonTable(scores);
  EXPECT_NE(table.find("the configured nominal model, not fitted"), std::string::npos) << table;
}

TEST(CalibrationJob, TestTableScoresTheNominalAtTimeOffsetZero)
{
  // A job at time offset 0.1 s (configured, not estimated): its test pairs are cut there, the
  // nominal row uses the same pairs re-cut at 0 from the test history, as the report does.
  const sim::GeneratedPairs data = simulatedPairs();
  const std::vector<EncoderSample> history = encoderHistory(data.pairs);
  CalibrationConfig config = diffDriveConfig(data.joints);
  config.collector.time_offset_s = 0.1;
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const std::vector<MotionPair> late = rewindowPairs(data.pairs, history, 0.1);
  const CalibrationJobResult job = runCalibrationJob(config, late, history, options);
  ASSERT_DOUBLE_EQ(job.time_offset_s, 0.1);
  const std::vector<ModelScore> scores = scoreModelsOnTest(config, job, late, history);
  ASSERT_EQ(scores.size(), 2u);
  const std::unique_ptr<MotionModel> nominal = makeModel("diff_drive", config.models);
  const ModelScore at_zero = scoreModel(*nominal, rewindowPairs(late, history, 0.0));
  const ModelScore at_job = scoreModel(*nominal, late);
  EXPECT_DOUBLE_EQ(scores[1].ate_m, at_zero.ate_m);
  EXPECT_DOUBLE_EQ(scores[1].rmse_xytheta(2), at_zero.rmse_xytheta(2));
  EXPECT_NE(at_zero.rmse_xytheta(2), at_job.rmse_xytheta(2));  // the re-cut matters
  // Without a history the nominal row takes the pairs as they are.
  EXPECT_DOUBLE_EQ(scoreModelsOnTest(config, job, late)[1].ate_m, at_job.ate_m);
}

TEST(CalibrationJob, ExitStatusFollowsConvergenceAndWarnings)
{
  ModelReport report;
  EXPECT_EQ(calibrationExitStatus(report), 0);
  report.warnings.push_back("separation not determined");
  EXPECT_EQ(calibrationExitStatus(report), 4);
  report.converged = false;
  EXPECT_EQ(calibrationExitStatus(report), 3);
}

// Issue 23 acceptance: a well-excited drive exits 0 without an observability warning; a drive
// without turns (straight ahead and back) warns about the wheel separation and exits 4.
TEST(CalibrationJob, WellExcitedDriveExitsZeroAndADriveWithoutTurnsWarnsAndExitsFour)
{
  sim::GeneratedPairs excited = simulatedPairs();
  const CalibrationConfig config = diffDriveConfig(excited.joints);
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult good = runCalibrationJob(config, excited.pairs, {}, options);
  EXPECT_TRUE(good.report.converged) << good.report.termination;
  EXPECT_TRUE(good.report.warnings.empty()) << good.report.warnings.front();
  EXPECT_EQ(calibrationExitStatus(good.report), 0);

  sim::PairGeneratorOptions straight;
  straight.robot = {"diff_drive",
                    {{"wheel_radius_left_m", kLeftRadiusM},
                     {"wheel_radius_right_m", kRightRadiusM},
                     {"wheel_separation_m", kSeparationM}}};
  straight.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  straight.interval_s = 0.5;
  straight.duration_s = 60.0;
  straight.motion.type = "scripted";
  for (int leg = 0; leg < 6; ++leg) {
    sim::ScriptedMotion motion;
    motion.duration_s = 5.0;
    motion.twist.vx_mps = leg % 2 == 0 ? 0.5 : -0.5;
    straight.motion.script.push_back(motion);
  }
  const sim::GeneratedPairs no_turns = sim::generatePairs(straight);
  const CalibrationJobResult bad = runCalibrationJob(config, no_turns.pairs, {}, options);
  bool names_separation = false;
  for (const std::string& warning : bad.report.warnings)
    names_separation |= warning.find("wheel_separation") != std::string::npos;
  EXPECT_TRUE(names_separation);
  EXPECT_EQ(calibrationExitStatus(bad.report), bad.report.converged ? 4 : 3);
  EXPECT_EQ(calibrationExitStatus(bad.report), 4) << bad.report.termination;
}

TEST(CalibrationJob, TestTableMarksAFitThatDidNotConverge)
{
  const sim::GeneratedPairs data = simulatedPairs();
  CalibrationConfig config = diffDriveConfig(data.joints);
  config.models.diff_drive.max_iterations = 1;
  config.models.diff_drive.yaw_starts = 1;
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult job = runCalibrationJob(config, data.pairs, {}, options);
  ASSERT_FALSE(job.report.converged);
  EXPECT_EQ(calibrationExitStatus(job.report), 3);
  const std::vector<MotionPair> test(data.pairs.begin(), data.pairs.begin() + 60);
  const std::vector<ModelScore> scores = scoreModelsOnTest(config, job, test);
  ASSERT_EQ(scores.size(), 2u);  // the model and the nominal row
  EXPECT_FALSE(scores[0].converged);
  EXPECT_TRUE(scores[1].converged);
  EXPECT_NE(formatComparisonTable(scores).find("NOT converged"), std::string::npos);
}

}  // namespace
}  // namespace odometry_calibration
