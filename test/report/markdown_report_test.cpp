// The reports never print a "before" that does not exist (issue 17): model-free fits (GP,
// linear) have no start values, so their residual line shows the fit's numbers alone, in the
// text report (formatModelReport) and in report.md (markdownReport).
#include "odometry_calibration/report/markdown_report.h"

#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/eval/model_report.h"

namespace odometry_calibration {
namespace {

ModelReport fitted(std::size_t before_count)
{
  ModelReport report;
  report.model = before_count > 0 ? "diff_drive" : "gp";
  report.pairs_used = 120;
  report.before = {0.0213, 0.0744, before_count};
  report.after = {0.0025, 0.0008, 120};
  return report;
}

std::string line(const std::string& text, const std::string& start)
{
  const std::size_t at = text.find(start);
  return at == std::string::npos ? "" : text.substr(at, text.find('\n', at) - at);
}

TEST(MarkdownReport, ModelFreeFitShowsNoBefore)
{
  const std::string text = line(formatModelReport(fitted(0)), "residual RMS per pair");
  EXPECT_EQ(text,
            "residual RMS per pair: translation 0.0025 m, rotation 0.00080 rad (no start values: "
            "nothing before the fit)");
  MarkdownReportInput input;
  input.bags = {"drive.bag"};
  input.trajectories.matched = input.trajectories.calibrated = {Pose2(), Pose2(1.0, 0.0, 0.0)};
  input.report = fitted(0);
  const std::string markdown = line(markdownReport(input), "Residual RMS per pair");
  EXPECT_NE(markdown.find("translation 0.0025 m, rotation 0.00080 rad"), std::string::npos)
      << markdown;
  EXPECT_EQ(markdown.find("→"), std::string::npos) << markdown;
  EXPECT_EQ(markdown.find("0.0213"), std::string::npos) << markdown;
}

TEST(MarkdownReport, ParametricFitShowsStartValuesThenFit)
{
  EXPECT_EQ(line(formatModelReport(fitted(120)), "residual RMS per pair"),
            "residual RMS per pair: translation 0.0213 m -> 0.0025 m, rotation 0.07440 rad -> "
            "0.00080 rad");
  MarkdownReportInput input;
  input.bags = {"drive.bag"};
  input.trajectories.matched = input.trajectories.calibrated = {Pose2(), Pose2(1.0, 0.0, 0.0)};
  input.report = fitted(120);
  const std::string markdown = line(markdownReport(input), "Residual RMS per pair");
  EXPECT_NE(markdown.find("0.0213 m → 0.0025 m"), std::string::npos) << markdown;
}

}  // namespace
}  // namespace odometry_calibration
