// The adequacy check: silent on simulated robots the differential-drive model describes, and
// naming the trend on one it cannot (a tracked base whose separation grows in tight turns;
// wheels that slip more at speed).
#include "odometry_calibration/eval/model_adequacy.h"

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/sim/pair_generator.h"

#include "support/diff_drive_start.h"

namespace odometry_calibration {
namespace {

/// A diff_drive fitted to 120 s of a robot's pairs, and the check of the fit on those pairs.
AdequacyCheck checkDiffDrive(std::map<std::string, double> deformation, unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  for (const auto& [key, value] : deformation)
    options.robot.parameters[key] = value;
  options.interval_s = 0.5;
  options.seed = seed;
  const sim::GeneratedPairs generated = sim::generatePairs(options);
  DiffDriveModel model(test::nominalDiffDriveOptions());
  model.fit(generated.pairs);
  return checkModelAdequacy(model, generated.pairs);
}

/// Every trend in words, for failure messages.
std::string allTrends(const AdequacyCheck& check)
{
  std::string text;
  for (const ResidualTrend& trend : check.trends)
    text += trend.text + "\n";
  return text;
}

const ResidualTrend* trendOf(const AdequacyCheck& check, const std::string& feature)
{
  for (const ResidualTrend& trend : check.trends) {
    if (trend.feature == feature)
      return &trend;
  }
  return nullptr;
}

TEST(ModelAdequacy, SilentOnRobotsTheModelDescribes)
{
  for (unsigned seed : {1u, 2u, 3u}) {
    const AdequacyCheck check = checkDiffDrive({}, seed);
    EXPECT_TRUE(check.fits) << check.text;
    EXPECT_EQ(check.trends.size(), 3u) << check.text;  // every feature tested
    EXPECT_NE(check.text.find("fits this robot"), std::string::npos) << check.text;
  }
}

TEST(ModelAdequacy, NamesTheCurvatureTrendOfATrackedBase)
{
  // Effective separation 20 % wider on the spot than driving straight.
  const AdequacyCheck check = checkDiffDrive({{"separation_growth", 0.2}}, 1);
  EXPECT_FALSE(check.fits) << check.text;
  const ResidualTrend* curvature = trendOf(check, "curvature");
  ASSERT_NE(curvature, nullptr);
  EXPECT_TRUE(curvature->significant) << allTrends(check);
  // One separation for all turns: tight turns turn less than it predicts, gentle ones more.
  EXPECT_GT(curvature->size, 0.05) << check.text;
  EXPECT_NE(check.text.find("the model does not fit this robot"), std::string::npos);
  EXPECT_NE(check.text.find("trends with curvature"), std::string::npos) << check.text;
}

TEST(ModelAdequacy, NamesTheSpeedTrendOfSlippingWheels)
{
  const AdequacyCheck check = checkDiffDrive({{"slip_per_speed", 0.1}}, 1);
  EXPECT_FALSE(check.fits) << check.text;
  const ResidualTrend* speed = trendOf(check, "speed");
  ASSERT_NE(speed, nullptr);
  EXPECT_TRUE(speed->significant) << check.text;
  // Slip shortens the real distance at speed: the fit over-predicts it there.
  EXPECT_GT(speed->size, 0.03) << check.text;
}

TEST(ModelAdequacy, AdvisesTheBestHeldOutModelOnlyWhenTheModelDoesNotFit)
{
  AdequacyCheck misfit;
  misfit.fits = false;
  ModelScore own, gp;
  own.model = "diff_drive";
  own.ate_m = 0.05;
  gp.model = "gp";
  gp.ate_m = 0.01;
  EXPECT_EQ(adequacyAdvice(misfit, "diff_drive", {own, gp}, "the held-out pairs"),
            "adequacy: recommended: gp, the best on the held-out pairs (ATE 0.0100 m against "
            "diff_drive's 0.0500 m)\n");
  EXPECT_NE(adequacyAdvice(misfit, "diff_drive", {}, "x").find("--holdout"), std::string::npos);
  EXPECT_EQ(adequacyAdvice(AdequacyCheck(), "diff_drive", {own, gp}, "x"), "");
}

}  // namespace
}  // namespace odometry_calibration
