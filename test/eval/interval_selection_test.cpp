#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/reference_pairs.h"
#include "odometry_calibration/eval/interval_selection.h"
#include "odometry_calibration/eval/metrics.h"

namespace odometry_calibration {
namespace {

const TricycleEncoderLayout kLayout;

TricycleParameters truth()
{
  return TricycleParameters::fromVectors(Eigen::Vector4d(0.55, 0.0108, 1.6, -0.07),
                                         Eigen::Vector3d(1.75, 0.03, 0.02));
}

TricycleParameters nominal()
{
  return TricycleParameters::fromVectors(Eigen::Vector4d(0.1, 0.0106141, 1.4, 0.0),
                                         Eigen::Vector3d(1.5, 0.0, 0.0));
}

/// A simulated tracker log at 25 Hz whose best keyframe interval lies inside the candidates:
/// the encoders are read at jittered times (each reading belongs to a moment up to
/// `jitter_s` [s] away from its stamp, as on the real log), which biases short windows (errors in
/// the inputs shrink the fitted scales, more the shorter the window), and the robot's heading
/// takes an unmodelled random walk of `heading_walk_rad` per sample (long windows carry more of
/// it, and there are fewer of them).
struct SimulatedLog
{
  std::vector<EncoderSample> samples;        ///< as recorded (jittered readings)
  std::vector<Pose2> T_world_sensor;         ///< as tracked (noise, the heading's walk)
  std::vector<EncoderSample> exact_samples;  ///< the readings at their stamps
};

SimulatedLog simulate(double duration_s, double jitter_s, double heading_walk_rad, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  SimulatedLog log;
  Pose2 T_world_sensor;
  double traction = 0.0;
  const int count = static_cast<int>(duration_s / 0.04) + 1;
  EncoderSample previous;
  for (int k = 0; k < count; ++k) {
    const double t = 0.04 * k;
    const double steering = std::round(1200.0 * std::sin(0.21 * t) + 400.0 * std::sin(0.9 * t));
    const double rate = 8000.0 * (std::sin(0.05 * t) > -0.3 ? 1.0 : -0.6) *
                        (1.0 + 0.3 * std::sin(1.7 * t));  // [ticks per 0.04 s]
    const EncoderSample exact{t, Eigen::Vector2d(steering, traction)};
    if (k > 0) {
      T_world_sensor = T_world_sensor *
                       predictTricycleSensorMotion(truth(), kLayout, {previous, exact}) *
                       Pose2(0.0, 0.0, heading_walk_rad * noise(rng));
    }
    previous = exact;
    log.exact_samples.push_back(exact);
    const double reading = traction + std::round(rate / 0.04 * jitter_s * noise(rng));
    log.samples.push_back({t, Eigen::Vector2d(steering, reading)});
    log.T_world_sensor.push_back(
        T_world_sensor * Pose2(0.002 * noise(rng), 0.002 * noise(rng), 0.0005 * noise(rng)));
    traction += std::round(rate);
  }
  return log;
}

Eigen::Matrix3d pairCovariance()
{
  return Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
}

/// Fits on `training` at `interval_s`; the ATE, over `test`'s exact readings, of the sensor
/// dead-reckoned with the fit against the sensor dead-reckoned with the truth: what the
/// calibration is worth, free of the test drive's own noise.
double calibrationError(const SimulatedLog& training, const SimulatedLog& test, double interval_s)
{
  const auto pairs =
      referencePairs(training.samples, training.T_world_sensor, interval_s, pairCovariance());
  const TricycleCalibrationResult fit = calibrateTricycle(pairs, kLayout, nominal(), {});
  return absoluteTrajectoryError(
      tricycleSensorTrajectory(fit.calibrated, kLayout, test.exact_samples, Pose2()),
      tricycleSensorTrajectory(truth(), kLayout, test.exact_samples, Pose2()));
}

SimulatedLog slice(const SimulatedLog& log, std::size_t first, std::size_t end)
{
  SimulatedLog part;
  part.samples.assign(log.samples.begin() + first, log.samples.begin() + end);
  part.exact_samples.assign(log.exact_samples.begin() + first, log.exact_samples.begin() + end);
  part.T_world_sensor.assign(log.T_world_sensor.begin() + first, log.T_world_sensor.begin() + end);
  return part;
}

TEST(IntervalSelection, ValidatesItsOptions)
{
  IntervalSelectionOptions options;
  EXPECT_NO_THROW(validate(options));
  options.candidates_s = {1.0, 0.5};
  EXPECT_THROW(validate(options), std::invalid_argument);
  options.candidates_s = {};
  EXPECT_THROW(validate(options), std::invalid_argument);
  options.candidates_s = {0.5, 1.0};
  options.fold_counts = {1};
  EXPECT_THROW(validate(options), std::invalid_argument);
  options.fold_counts = {};
  EXPECT_THROW(validate(options), std::invalid_argument);
}

TEST(IntervalSelection, ACandidateLeavingAFoldTooFewPairsScoresInfinity)
{
  const SimulatedLog log = simulate(40.0, 0.0, 0.0, 3);
  IntervalSelectionOptions options;
  options.candidates_s = {0.5, 8.0};  // 8 s: 5 pairs in all, fewer than 7 outside any block
  options.fold_counts = {2};
  const IntervalChoice choice = chooseTricycleInterval(log.samples, log.T_world_sensor, kLayout,
                                                       nominal(), {}, pairCovariance(), options);
  ASSERT_EQ(choice.curve.size(), 2u);
  EXPECT_TRUE(std::isfinite(choice.curve[0].validation_ate_m));
  EXPECT_TRUE(std::isinf(choice.curve[1].validation_ate_m));
  EXPECT_DOUBLE_EQ(choice.interval_s, 0.5);
  options.candidates_s = {8.0};
  EXPECT_THROW(chooseTricycleInterval(log.samples, log.T_world_sensor, kLayout, nominal(), {},
                                      pairCovariance(), options),
               std::invalid_argument);
}

TEST(IntervalSelection, ChoosesAnIntervalAsGoodAsTheBestOnUnseenData)
{
  const SimulatedLog log = simulate(300.0, 0.02, 0.0005, 5);
  const std::size_t split = log.samples.size() * 6 / 10;
  const SimulatedLog training = slice(log, 0, split);
  const SimulatedLog test = slice(log, split, log.samples.size());
  IntervalSelectionOptions options;
  options.candidates_s = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
  const IntervalChoice choice = chooseTricycleInterval(
      training.samples, training.T_world_sensor, kLayout, nominal(), {}, pairCovariance(), options);
  ASSERT_EQ(choice.curve.size(), options.candidates_s.size());
  // The truth: each candidate's calibration error on the unseen 40 %. This drive's best interval
  // is 4 s (error 0.012 m); 0.25 s windows are 7x worse (the jitter's bias), 8 s 3x (the walk,
  // few pairs).
  std::vector<double> error_m;
  for (const IntervalScore& score : choice.curve) {
    error_m.push_back(calibrationError(training, test, score.interval_s));
    std::printf("T %.2f s: validation %.4f m, calibration error on unseen data %.4f m\n",
                score.interval_s, score.validation_ate_m, error_m.back());
  }
  const std::size_t best =
      static_cast<std::size_t>(std::min_element(error_m.begin(), error_m.end()) - error_m.begin());
  const std::size_t chosen = static_cast<std::size_t>(
      std::find(options.candidates_s.begin(), options.candidates_s.end(), choice.interval_s) -
      options.candidates_s.begin());
  ASSERT_LT(chosen, options.candidates_s.size());
  EXPECT_DOUBLE_EQ(options.candidates_s[best], 4.0);
  // Cross-validation on the training part alone lands next to it (2 s), far from the extremes.
  EXPECT_LE(chosen > best ? chosen - best : best - chosen, 1u) << choice.interval_s;
  EXPECT_LT(error_m[chosen], 1.5 * error_m[best]);
  EXPECT_LT(error_m[chosen], 0.25 * error_m.front());
  EXPECT_LT(error_m[chosen], 0.5 * error_m.back());
}

}  // namespace
}  // namespace odometry_calibration
