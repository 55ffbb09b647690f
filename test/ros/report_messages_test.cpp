#include "odometry_calibration/ros/report_messages.h"

#include <cmath>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

// Issue 17: a model-free fit has no "before"; the message says so with NaN, never with a 0
// that reads as a perfect start.
TEST(ReportMessages, BeforeIsNaNWithoutStartValues)
{
  ModelReport report;
  report.model = "gp";
  report.after = {0.0025, 0.0008, 120};
  const auto msg = ros_conversions::toReportMsg(report, 130, 0.0);
  EXPECT_TRUE(std::isnan(msg.residual_rms_translation_before_m));
  EXPECT_TRUE(std::isnan(msg.residual_rms_rotation_before_rad));
  EXPECT_DOUBLE_EQ(msg.residual_rms_translation_after_m, 0.0025);

  report.model = "diff_drive";
  report.before = {0.0213, 0.0744, 120};
  const auto fitted = ros_conversions::toReportMsg(report, 130, 0.0);
  EXPECT_DOUBLE_EQ(fitted.residual_rms_translation_before_m, 0.0213);
  EXPECT_DOUBLE_EQ(fitted.residual_rms_rotation_before_rad, 0.0744);
}

}  // namespace
}  // namespace odometry_calibration
