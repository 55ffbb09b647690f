// Observability warnings (issue 23): a warning only when a parameter is not determined; strong
// correlations of determined parameters are notes.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/models/observability.h"

namespace odometry_calibration {
namespace {

/// 40 pairs of 0.2 m, turning 0.1 rad left and right in turn: 8 m, 2 rad each way.
std::vector<MotionPair> wellExcitedPairs()
{
  std::vector<MotionPair> pairs(40);
  for (std::size_t i = 0; i < pairs.size(); ++i)
    pairs[i].sensor_motion = Pose2(0.2, 0.0, i % 2 == 0 ? 0.1 : -0.1);
  return pairs;
}

ObservabilityHints hints()
{
  ObservabilityHints h;
  h.unobservable_without_turning = "wheel_separation";
  h.confused_by_one_way_turns = "the radii's difference";
  h.relative_parameters = {"left_wheel_radius", "wheel_separation"};
  return h;
}

/// Radius and separation each to 0.3 %, correlated `correlation`.
Eigen::MatrixXd covariance(const std::vector<ParameterEstimate>& estimates, double correlation)
{
  Eigen::MatrixXd c(2, 2);
  c << std::pow(estimates[0].sigma, 2), correlation * estimates[0].sigma * estimates[1].sigma,
      correlation * estimates[0].sigma * estimates[1].sigma, std::pow(estimates[1].sigma, 2);
  return c;
}

TEST(Observability, CorrelatedButDeterminedParametersAreANoteNotAWarning)
{
  // The case: radii and separation determined to 0.3 %, correlation 0.999.
  const std::vector<ParameterEstimate> estimates = {
      {"left_wheel_radius", "m", 0.021, 0.0210, 0.003 * 0.0210},
      {"wheel_separation", "m", 0.09, 0.0885, 0.003 * 0.0885}};
  std::vector<std::string> notes;
  const std::vector<std::string> warnings = observabilityWarnings(
      wellExcitedPairs(), estimates, covariance(estimates, 0.999), true, hints(), &notes);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("left_wheel_radius and wheel_separation are strongly correlated"),
            std::string::npos)
      << notes[0];
}

TEST(Observability, APoorlyDeterminedParameterWarnsAndItsCorrelationIsNoNote)
{
  const std::vector<ParameterEstimate> estimates = {
      {"left_wheel_radius", "m", 0.021, 0.0210, 0.003 * 0.0210},
      {"wheel_separation", "m", 0.09, 0.0885, 0.2 * 0.0885}};  // 20 %: not determined
  std::vector<std::string> notes;
  const std::vector<std::string> warnings = observabilityWarnings(
      wellExcitedPairs(), estimates, covariance(estimates, 0.999), true, hints(), &notes);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("wheel_separation is poorly determined"), std::string::npos);
  EXPECT_TRUE(notes.empty());
}

TEST(Observability, ADriveWithoutTurnsWarnsAboutTheSeparation)
{
  std::vector<MotionPair> straight(40);
  for (std::size_t i = 0; i < straight.size(); ++i)
    straight[i].sensor_motion = Pose2(i % 2 == 0 ? 0.2 : -0.2, 0.0, 0.001);
  const std::vector<ParameterEstimate> estimates = {
      {"left_wheel_radius", "m", 0.021, 0.0210, 0.003 * 0.0210},
      {"wheel_separation", "m", 0.09, 0.0885, 0.003 * 0.0885}};
  const std::vector<std::string> warnings = observabilityWarnings(
      straight, estimates, covariance(estimates, 0.5), true, hints(), nullptr);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("no turning: wheel_separation"), std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace odometry_calibration
