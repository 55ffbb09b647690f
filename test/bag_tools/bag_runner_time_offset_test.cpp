// The session's pairing at the estimated time offset, on a bag: a bag paired at a wrong
// configured time offset is paired again at the estimated one, so that each scan's sweep
// compensation uses the motion of its own instant. On a simulated Mines-like run (every sensor
// effect on, true offset 0) with config/mines.yaml's -0.15 s, pairs made at -0.15 s give the mean
// wheel radius 0.8 % short.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/models/diff_drive_model.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

class BagRunnerTimeOffset : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/bag_runner_time_offset_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    scenario_ =
        sim::loadScenarioYaml(kConfig + "/sim/scenarios/mines_like.yaml", kConfig + "/sim/worlds");
    scenario_.seed = 1;
    scenario_.duration_s = kDurationS;
    bag_ = directory_ + "/mines_like.bag";
    simulateToBag(scenario_, bag_, "");
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(directory_); }

  /// The mean of the fitted wheel radii [m].
  static double meanRadius(const CalibrationConfig& config, const BagRunResult& run)
  {
    CalibrationJobOptions options;
    options.compare_trajectories = false;
    const CalibrationJobResult job =
        runCalibrationJob(config, run.pairs, run.encoder_history, options);
    const auto* model = dynamic_cast<const DiffDriveModel*>(job.model.get());
    EXPECT_NE(model, nullptr);
    return model ? 0.5 * (model->intrinsics()(0) + model->intrinsics()(1)) : NAN;
  }

  static double trueMeanRadius()
  {
    return 0.5 * (scenario_.robot.parameters.at("wheel_radius_left_m") +
                  scenario_.robot.parameters.at("wheel_radius_right_m"));
  }

  static constexpr double kDurationS = 120.0;
  static std::string directory_, bag_;
  static sim::Scenario scenario_;
};
std::string BagRunnerTimeOffset::directory_, BagRunnerTimeOffset::bag_;
sim::Scenario BagRunnerTimeOffset::scenario_;

/// The bags run once and fitted by the session (which pairs them again at the estimated time
/// offset when the configured one is off): the run with the session's pairs, `config` at the
/// offset they were paired at.
BagRunResult runAtEstimatedOffset(const std::vector<std::string>& bags, CalibrationConfig* config,
                                  double end_s, OffsetPairing* pairing)
{
  BagRunResult run = runBags(bags, *config, 0.0, end_s);
  const CalibrateOutcome outcome = run.session->calibrate({}).outcome;
  const CalibrationSession& session = run.session->source(0);
  run.pairs = session.pairs();
  run.encoder_history = session.encoderHistory();
  if (pairing)
    *pairing = outcome.fit->offset_pairing;
  config->collector.time_offset_s = session.timeOffset();
  return run;
}

TEST_F(BagRunnerTimeOffset, PairsAgainAtTheEstimateAndFitsTheTrueRadius)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/mines.yaml");
  ASSERT_NEAR(config.collector.time_offset_s, -0.15, 1e-9);  // the simulated truth is 0
  ASSERT_TRUE(config.estimate_time_offset);
  OffsetPairing pairing;
  const BagRunResult run = runAtEstimatedOffset({bag_}, &config, 0.0, &pairing);
  EXPECT_TRUE(pairing.paired_again) << pairing.text;
  EXPECT_NEAR(pairing.configured_s, -0.15, 1e-9);
  EXPECT_NEAR(pairing.estimate_s, 0.0, 0.02);
  EXPECT_NEAR(config.collector.time_offset_s, pairing.estimate_s, 1e-12);
  EXPECT_NE(pairing.text.find("paired again"), std::string::npos);
  // Paired at -0.15 s and only re-cut at the estimate, the radius reads -0.80 %.
  const double error = meanRadius(config, run) / trueMeanRadius() - 1.0;
  EXPECT_LT(std::abs(error), 0.004) << "mean radius error " << 100.0 * error << " %";
}

TEST_F(BagRunnerTimeOffset, ResultDoesNotDependOnTheConfiguredOffset)
{
  // Configured at the truth: one pass; configured 0.15 s off: two passes, the same radii.
  CalibrationConfig at_truth = loadCalibrationConfig(kConfig + "/mines.yaml");
  at_truth.collector.time_offset_s = 0.0;
  OffsetPairing once;
  const BagRunResult run_at_truth = runAtEstimatedOffset({bag_}, &at_truth, 0.0, &once);
  EXPECT_FALSE(once.paired_again) << once.text;
  EXPECT_NE(once.text.find("paired at the configured time offset"), std::string::npos);
  CalibrationConfig off = loadCalibrationConfig(kConfig + "/mines.yaml");
  const BagRunResult run_off = runAtEstimatedOffset({bag_}, &off, 0.0, nullptr);
  const double at_truth_radius = meanRadius(at_truth, run_at_truth);
  EXPECT_NEAR(meanRadius(off, run_off), at_truth_radius, 0.002 * at_truth_radius);
}

TEST_F(BagRunnerTimeOffset, WithoutEstimationPairsOnceAtTheConfiguredOffset)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/mines.yaml");
  config.estimate_time_offset = false;
  OffsetPairing pairing;
  const BagRunResult run = runAtEstimatedOffset({bag_}, &config, 20.0, &pairing);
  EXPECT_FALSE(pairing.paired_again);
  EXPECT_EQ(pairing.text, "");
  EXPECT_NEAR(config.collector.time_offset_s, -0.15, 1e-12);
  EXPECT_EQ(run.pairs.size(), runBags({bag_}, config, 0.0, 20.0).pairs.size());
}

}  // namespace
}  // namespace odometry_calibration
