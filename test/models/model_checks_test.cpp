#include "odometry_calibration/models/model_checks.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

/// The message of the std::invalid_argument `call` throws ("" when it throws none).
template <class Call>
std::string refusal(Call call)
{
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

EncoderSample sample(double stamp_s, int joints)
{
  return {stamp_s, Eigen::VectorXd::Zero(joints)};
}

MotionPair pairWith(int samples, int joints)
{
  MotionPair pair;
  for (int k = 0; k < samples; ++k)
    pair.encoder_samples.push_back(sample(0.1 * k, joints));
  return pair;
}

TEST(ModelChecks, TooFewPairsAreNamedWithTheAdvice)
{
  const std::vector<MotionPair> five(5, pairWith(2, 2));
  EXPECT_EQ(refusal([&] { requireEnoughPairs(five, 5, "diff_drive calibration"); }), "");
  EXPECT_EQ(refusal([&] { requireEnoughPairs(five, 6, "diff_drive calibration"); }),
            "diff_drive calibration needs at least 6 keyframe pairs, got 5: record a longer "
            "drive");
  EXPECT_EQ(refusal([&] { requireEnoughPairs(five, 7, "tricycle calibration", "shorten T"); }),
            "tricycle calibration needs at least 7 keyframe pairs, got 5: shorten T");
}

TEST(ModelChecks, EveryPairNeedsTwoSamplesWithTheJoints)
{
  std::vector<MotionPair> pairs(3, pairWith(3, 4));
  EXPECT_EQ(refusal([&] { requirePairsWithJoints(pairs, {0, 3}, "mecanum", "all four"); }), "");
  EXPECT_EQ(refusal([&] {
              requirePairsWithJoints(pairs, {1, 4}, "mecanum", "all four");
            }),
            "mecanum: every pair needs two or more encoder samples with all four");
  pairs[2] = pairWith(1, 4);
  EXPECT_EQ(refusal([&] {
              requirePairsWithJoints(pairs, {0, 1}, "diff_drive", "both");
            }),
            "diff_drive: every pair needs two or more encoder samples with both");
}

TEST(ModelChecks, APredictionNeedsTwoSamplesCarryingTheJoints)
{
  const std::vector<EncoderSample> two = {sample(0.0, 2), sample(0.1, 2)};
  EXPECT_EQ(refusal([&] { requirePredictionSamples(two, {0, 1}, "diff_drive", "wheels"); }), "");
  EXPECT_EQ(refusal([&] {
              requirePredictionSamples({two[0]}, {0, 1}, "diff_drive", "wheels");
            }),
            "diff_drive prediction needs at least two encoder samples");
  EXPECT_EQ(refusal([&] {
              requirePredictionSamples(two, {0, 2}, "tricycle", "joints");
            }),
            "tricycle: the model's joints (indices 0, 2) are not among the samples' 2 joints");
}

TEST(ModelChecks, JointsMustBeAmongThePairs)
{
  EXPECT_EQ(refusal([] { requireJointsAmong({0, 2}, 3, "diff_drive: the wheel joints"); }), "");
  EXPECT_EQ(refusal([] {
              requireJointsAmong({0, 3}, 3, "diff_drive: the wheel joints");
            }),
            "diff_drive: the wheel joints are not among the pairs' 3 joints");
}

TEST(ModelChecks, DistinctJointIndices)
{
  EXPECT_TRUE(distinctJointIndices({0, 1}));
  EXPECT_TRUE(distinctJointIndices({3, 0, 2, 1}));
  EXPECT_FALSE(distinctJointIndices({1, 1}));
  EXPECT_FALSE(distinctJointIndices({0, 2, 1, 2}));
  EXPECT_FALSE(distinctJointIndices({-1, 0}));
}

TEST(ModelChecks, OptionsMustBePositiveAndTheSolverLimitsInRange)
{
  EXPECT_EQ(refusal([] { requirePositiveOption(0.1, "skid_steer", "wheel_radius_m"); }), "");
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_EQ(refusal([&] { requirePositiveOption(bad, "skid_steer", "wheel_radius_m"); }),
              "skid_steer option 'wheel_radius_m' must be > 0")
        << bad;
  }
  EXPECT_EQ(refusal([] { requireSolverLimits(1, 360, "mecanum"); }), "");
  EXPECT_EQ(refusal([] { requireSolverLimits(0, 8, "mecanum"); }),
            "mecanum option 'max_iterations' must be >= 1");
  EXPECT_EQ(refusal([] { requireSolverLimits(500, 0, "diff_drive"); }),
            "diff_drive option 'yaw_starts' must be in [1, 360]");
  EXPECT_EQ(refusal([] { requireSolverLimits(500, 361, "diff_drive"); }),
            "diff_drive option 'yaw_starts' must be in [1, 360]");
}

TEST(ModelChecks, UnphysicalFittedParametersAreNamed)
{
  const std::vector<std::string> names = {"left_wheel_radius", "right_wheel_radius",
                                          "wheel_separation",  "sensor_x",
                                          "sensor_y",          "sensor_theta"};
  EXPECT_EQ(physicalBoundsProblem(names, {0.0765, 0.0775, 0.32, 0.145, 0.01, 0.02}), "");
  EXPECT_NE(physicalBoundsProblem(names, {77.0, 0.0775, 0.32, 0.145, 0.01, 0.02})
                .find("left_wheel_radius = 77 is outside (0, 5] m"),
            std::string::npos);
  EXPECT_NE(physicalBoundsProblem(names, {0.0765, -0.0775, 0.32, 0.145, 0.01, 0.02})
                .find("right_wheel_radius = -0.0775"),
            std::string::npos);
  EXPECT_NE(physicalBoundsProblem(names, {0.0765, 0.0775, 0.0, 0.145, 0.01, 0.02})
                .find("wheel_separation = 0 is outside (0, 50] m"),
            std::string::npos);
  EXPECT_NE(physicalBoundsProblem(names, {0.0765, 0.0775, 0.32, 1e10, 0.01, 0.02})
                .find("sensor_x = 1e+10 puts the sensor more than 100 m"),
            std::string::npos);
  EXPECT_NE(physicalBoundsProblem(names, {0.0765, 0.0775, 0.32, 0.145, 0.01, std::nan("")})
                .find("sensor_theta = nan is not finite"),
            std::string::npos);
  // A model-free model's parameters: only finite.
  EXPECT_EQ(physicalBoundsProblem({"log_length_scale"}, {-40.0}), "");
}

}  // namespace
}  // namespace odometry_calibration
