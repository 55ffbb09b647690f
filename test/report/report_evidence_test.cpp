// The report's building blocks: chained trajectories and per-pair errors, histograms, the
// gnuplot runner's messages, the staged plot folder.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/common/gnuplot.h"
#include "odometry_calibration/common/histogram.h"
#include "odometry_calibration/common/staged_directory.h"
#include "odometry_calibration/eval/trajectory_comparison.h"
#include "odometry_calibration/report/report_plots.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Predicts `scale` times the first encoder value's increment straight ahead.
class ScaleModel : public MotionModel
{
public:
  explicit ScaleModel(double scale) : scale_(scale) {}
  std::string name() const override { return "scale"; }
  ModelReport fit(const std::vector<MotionPair>&) override { return {}; }
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override
  {
    MotionPrediction prediction;
    prediction.mean =
        Pose2(scale_ * (samples.back().values(0) - samples.front().values(0)), 0.0, 0.1);
    return prediction;
  }
  std::string toYaml() const override { return ""; }

private:
  double scale_;
};

MotionPair pair(double start_s, double end_s, double ticks, const Pose2& motion)
{
  MotionPair p;
  p.start_stamp_s = start_s;
  p.end_stamp_s = end_s;
  p.encoder_samples = {{start_s, Eigen::VectorXd::Constant(1, 0.0)},
                       {end_s, Eigen::VectorXd::Constant(1, ticks)}};
  p.sensor_motion = motion;
  return p;
}

TEST(TrajectoryComparison, ChainsMeasurementsAndPredictionsOverTheSameIntervals)
{
  const std::vector<MotionPair> pairs = {pair(0.0, 0.5, 10, Pose2(1.0, 0.0, 0.1)),
                                         pair(0.5, 1.0, 10, Pose2(1.0, 0.0, 0.1)),
                                         pair(1.5, 2.0, 10, Pose2(1.0, 0.0, 0.1))};  // gap
  const ScaleModel calibrated(0.1), nominal(0.12);
  // The nominal pairs lack the second interval: it is left out of all three.
  const std::vector<MotionPair> nominal_pairs = {pairs[0], pairs[2]};
  const TrajectoryComparison c = compareTrajectories(pairs, calibrated, nominal_pairs, &nominal);
  ASSERT_EQ(c.stamps_s.size(), 3u);
  EXPECT_EQ(c.stamps_s, (std::vector<double>{0.0, 0.5, 2.0}));
  EXPECT_EQ(c.gaps, 1u);
  // Both measured steps are (1, 0, 0.1): the second starts turned by 0.1 rad.
  EXPECT_NEAR(c.matched[2].x(), 1.0 + std::cos(0.1), 1e-12);
  EXPECT_NEAR(c.matched[2].y(), std::sin(0.1), 1e-12);
  EXPECT_NEAR(c.matched[2].theta(), 0.2, 1e-12);
  EXPECT_NEAR(c.calibrated[2].x(), c.matched[2].x(), 1e-12);  // exact model
  EXPECT_NEAR(c.nominal[2].x(), 1.2 * c.matched[2].x(), 1e-12);
  ASSERT_EQ(c.nominal_errors.size(), 2u);
  EXPECT_NEAR(translationErrors(c.nominal_errors)[1], 0.2, 1e-12);
  EXPECT_NEAR(translationErrors(c.calibrated_errors)[0], 0.0, 1e-12);
  EXPECT_NEAR(rotationErrors(c.nominal_errors)[0], 0.0, 1e-12);
  // Without a nominal model: every pair, no nominal trajectory.
  const TrajectoryComparison alone = compareTrajectories(pairs, calibrated, {}, nullptr);
  EXPECT_EQ(alone.calibrated_errors.size(), 3u);
  EXPECT_TRUE(alone.nominal.empty());
  EXPECT_THROW(compareTrajectories({}, calibrated, {}, nullptr), std::invalid_argument);
}

TEST(TrajectoryComparison, MedianIsTheUpperMiddleValue)
{
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 3.0);
  EXPECT_EQ(median({}), 0.0);
}

TEST(Histogram, CountsValuesIntoEqualBinsAndOverflow)
{
  const Histogram h = makeHistogram({0.0, 0.09, 0.1, 0.35, -0.2, 0.4, 7.0, NAN}, 0.4, 4);
  EXPECT_DOUBLE_EQ(h.bin_width, 0.1);
  EXPECT_EQ(h.counts, (std::vector<std::size_t>{3, 1, 0, 1}));
  EXPECT_EQ(h.overflow, 3u);  // 0.4 (the upper edge is open), 7, NaN
  EXPECT_THROW(makeHistogram({1.0}, 0.0, 4), std::invalid_argument);
  EXPECT_THROW(makeHistogram({1.0}, 1.0, 0), std::invalid_argument);
  // The common limit: the quantile of both sets, just above it so it lands in the last bin.
  const double upper = histogramUpperLimit({{1, 2, 3, 4, 5}, {6, 7, 8, 9, 10}}, 0.9, 0.001);
  EXPECT_GT(upper, 10.0);
  EXPECT_LT(upper, 10.01);
  EXPECT_EQ(makeHistogram({10.0}, upper, 10).counts.back(), 1u);
  EXPECT_EQ(histogramUpperLimit({{0.0, 0.0}}, 0.98, 0.5), 0.5);
}

class ReportFiles : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/report_evidence_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(directory_); }
  std::string directory_;
};

TEST_F(ReportFiles, GnuplotProblemsAreMessagesNotExceptions)
{
  GnuplotOptions missing;
  missing.program = "no-such-plotter-xyz";
  EXPECT_NE(runGnuplot({"a.gp"}, directory_, missing).find("gnuplot-nox"), std::string::npos);
  // A script with an error: gnuplot's own message is passed on.
  std::ofstream(directory_ + "/bad.gp") << "plot 'no_such_file.dat' using 1:2\n";
  const std::string message = runGnuplot({"bad.gp"}, directory_);
  EXPECT_NE(message.find("failed"), std::string::npos) << message;
  EXPECT_NE(message.find("no_such_file.dat"), std::string::npos) << message;
  std::ofstream(directory_ + "/good.gp") << "set terminal pngcairo size 200,100\n"
                                            "set output 'good.png'\nplot x\n";
  EXPECT_EQ(runGnuplot({"good.gp"}, directory_), "");
  EXPECT_TRUE(isPngFile(directory_ + "/good.png"));
  EXPECT_FALSE(isPngFile(directory_ + "/good.gp"));
  EXPECT_FALSE(fs::exists(directory_ + "/.gnuplot_stderr"));
}

TEST_F(ReportFiles, PlotsOfATinyComparison)
{
  const std::vector<MotionPair> pairs = {pair(0.0, 0.5, 10, Pose2(1.0, 0.0, 0.1)),
                                         pair(0.5, 1.0, 10, Pose2(1.0, 0.05, 0.1))};
  const ScaleModel calibrated(0.1), nominal(0.12);
  ReportPlotInput input;
  input.trajectories = compareTrajectories(pairs, calibrated, pairs, &nominal);
  input.calibrated_label = "scale";
  ReportPlots plots = writeReportPlots(input, directory_);
  EXPECT_EQ(plots.problem, "");
  EXPECT_EQ(plots.images, (std::vector<std::string>{kTrajectoryPlot, kResidualPlot}));
  input.time_offset_curve = {{-0.1, 3.0}, {0.0, 1.0}, {0.1, 2.5}};
  plots = writeReportPlots(input, directory_);
  EXPECT_TRUE(plots.has(kTimeOffsetPlot));
  // An unwritable folder: a problem, no exception.
  plots = writeReportPlots(input, directory_ + "/missing");
  EXPECT_NE(plots.problem.find("could not be written"), std::string::npos) << plots.problem;
  EXPECT_TRUE(plots.images.empty());
}

TEST_F(ReportFiles, StagedFolderAppearsWholeOrNotAtAll)
{
  {
    StagedDirectory staged(directory_, "plots");
    std::ofstream(staged.path() + "/a.txt") << "first";
    EXPECT_FALSE(fs::exists(directory_ + "/plots"));
  }  // not committed: gone
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 0);
  {
    StagedDirectory staged(directory_, "plots");
    std::ofstream(staged.path() + "/a.txt") << "first";
    staged.commit();
  }
  {
    StagedDirectory staged(directory_, "plots");
    std::ofstream(staged.path() + "/b.txt") << "second";
    staged.commit();  // replaces the old folder as a whole
  }
  EXPECT_FALSE(fs::exists(directory_ + "/plots/a.txt"));
  EXPECT_TRUE(fs::exists(directory_ + "/plots/b.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 1);
  EXPECT_THROW(StagedDirectory(directory_ + "/missing", "plots"), std::runtime_error);
}

}  // namespace
}  // namespace odometry_calibration
