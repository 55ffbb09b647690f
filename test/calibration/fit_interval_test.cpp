// Choosing the keyframe interval of laser pairs by time-blocked cross-validation, scored by the
// criterion of scan matching (the RPE).
#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

/// The criterion of scan-matched pairs (fitIntervalCriterion of a laser).
constexpr FitIntervalCriterion kRpe = FitIntervalCriterion::kRpe;

/// Noise-free pairs of one drive (same seed, same plan) at keyframe interval `interval_s`.
sim::GeneratedPairs drive(double interval_s)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  options.duration_s = 120.0;
  options.interval_s = interval_s;
  options.translation_noise_m = 0.0;
  options.rotation_noise_rad = 0.0;
  return sim::generatePairs(options);
}

/// The pairs with a matcher's error that does not shrink with T: Gaussian noise of sigma_m and
/// sigma_rad per pair, and the translation scaled by (1 + scale_error).
std::vector<MotionPair> measured(std::vector<MotionPair> pairs, double sigma_m, double sigma_rad,
                                 unsigned seed, double scale_error = 0.0)
{
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  for (MotionPair& pair : pairs) {
    const Pose2& truth = pair.sensor_motion;
    pair.sensor_motion = Pose2(truth.x() * (1.0 + scale_error) + sigma_m * normal(random),
                               truth.y() * (1.0 + scale_error) + sigma_m * normal(random),
                               truth.theta() + sigma_rad * normal(random));
    pair.covariance =
        Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  }
  return pairs;
}

CalibrationConfig diffDriveConfig(const JointLayout& joints)
{
  CalibrationConfig config;
  config.model = "diff_drive";
  config.models.joints = joints;
  config.models.diff_drive.initial_left_radius_m = 0.077;
  config.models.diff_drive.initial_right_radius_m = 0.077;
  config.models.diff_drive.initial_separation_m = 0.33;
  config.models.diff_drive.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return config;
}

TEST(FitInterval, LongerPairsWinWhenTheMatchersErrorDoesNotShrinkWithT)
{
  // The same 1 cm / 10 mrad per pair at every T: a 1 s pair's displacement is three times
  // larger than a 0.3 s pair's, so its fit is better, and the validation must say so.
  const sim::GeneratedPairs short_pairs = drive(0.3), long_pairs = drive(1.0);
  const sim::GeneratedPairs evaluation = drive(0.5);
  const CalibrationConfig config = diffDriveConfig(short_pairs.joints);
  const std::vector<IntervalPairs> candidates = {{0.3, measured(short_pairs.pairs, 0.01, 0.01, 1)},
                                                 {1.0, measured(long_pairs.pairs, 0.01, 0.01, 2)}};
  const FitIntervalChoice choice =
      chooseFitInterval(config, candidates, measured(evaluation.pairs, 0.0005, 0.0005, 3), kRpe);
  ASSERT_EQ(choice.curve.size(), 2u);
  std::cout << formatFitIntervalChoice(choice, 0.5);
  EXPECT_EQ(choice.interval_s, 1.0);
  EXPECT_EQ(choice.curve[0].pairs, candidates[0].pairs.size());
  EXPECT_EQ(choice.curve[0].blocks, 7u);  // 3 + 4 blocks
  EXPECT_LT(choice.curve[1].validation_error_m, 0.9 * choice.curve[0].validation_error_m);
  const std::string text = formatFitIntervalChoice(choice, 0.5);
  EXPECT_NE(text.find("1.00 s"), std::string::npos) << text;
  EXPECT_NE(text.find("(chosen)"), std::string::npos) << text;
  EXPECT_NE(text.find("validation RPE of 0.50 s pairs"), std::string::npos) << text;
}

TEST(FitInterval, ABiasedCandidateLoses)
{
  // The 1 s pairs read 3 % long (a matcher's scale error): their radii come out 3 % large and
  // the held-out blocks' odometry drifts; the unbiased 0.5 s pairs win despite more noise.
  const sim::GeneratedPairs half = drive(0.5), one = drive(1.0);
  const CalibrationConfig config = diffDriveConfig(half.joints);
  const std::vector<MotionPair> evaluation = measured(half.pairs, 0.001, 0.001, 4);
  const FitIntervalChoice choice =
      chooseFitInterval(config,
                        {{0.5, measured(half.pairs, 0.003, 0.003, 5)},
                         {1.0, measured(one.pairs, 0.003, 0.003, 6, 0.03)}},
                        evaluation, kRpe);
  std::cout << formatFitIntervalChoice(choice, 0.5);
  EXPECT_EQ(choice.interval_s, 0.5);
  EXPECT_GT(choice.curve[1].validation_error_m, 1.5 * choice.curve[0].validation_error_m);
}

TEST(FitInterval, BadInputIsAClearError)
{
  sim::GeneratedPairs half = drive(0.5);
  half.pairs = measured(half.pairs, 0.002, 0.002, 7);
  const CalibrationConfig config = diffDriveConfig(half.joints);
  EXPECT_THROW(chooseFitInterval(config, {}, half.pairs, kRpe), std::invalid_argument);
  FitIntervalOptions one_block;
  one_block.fold_counts = {1};
  EXPECT_THROW(chooseFitInterval(config, {{0.5, half.pairs}}, half.pairs, kRpe, one_block),
               std::invalid_argument);
  // Five evaluation pairs cannot be cut into four blocks of two.
  const std::vector<MotionPair> few(half.pairs.begin(), half.pairs.begin() + 5);
  EXPECT_THROW(chooseFitInterval(config, {{0.5, half.pairs}}, few, kRpe), std::invalid_argument);
  // A candidate with too few pairs to fit scores infinity; with no other, it is an error.
  const std::vector<MotionPair> three(half.pairs.begin(), half.pairs.begin() + 3);
  EXPECT_THROW(chooseFitInterval(config, {{0.5, three}}, half.pairs, kRpe), std::invalid_argument);
  const FitIntervalChoice choice =
      chooseFitInterval(config, {{0.3, three}, {0.5, half.pairs}}, half.pairs, kRpe);
  EXPECT_EQ(choice.interval_s, 0.5);
  EXPECT_FALSE(std::isfinite(choice.curve[0].validation_error_m));
}

TEST(FitInterval, PairsEndingByTheBorder)
{
  const sim::GeneratedPairs half = drive(0.5);
  const double border = half.pairs[10].end_stamp_s;
  const std::vector<MotionPair> before = pairsEndingBy(half.pairs, border);
  ASSERT_EQ(before.size(), 11u);
  EXPECT_DOUBLE_EQ(before.back().end_stamp_s, border);
}

TEST(FitInterval, PairsStartingFromTheBorder)
{
  const sim::GeneratedPairs half = drive(0.5);
  const double border = half.pairs[10].start_stamp_s;
  const std::vector<MotionPair> after = pairsStartingFrom(half.pairs, border);
  ASSERT_EQ(after.size(), half.pairs.size() - 10u);
  EXPECT_DOUBLE_EQ(after.front().start_stamp_s, border);
  for (const MotionPair& pair : after)
    EXPECT_GE(pair.start_stamp_s, border);
}

}  // namespace
}  // namespace odometry_calibration
