// The keyframe interval of a tracker's poses chosen by calibration/fit_interval.h with the
// criterion of absolute poses (the ATE of each block's chained pairs), on simulated tracker logs.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/data/reference_pairs.h"
#include "odometry_calibration/eval/metrics.h"
#include "odometry_calibration/models/tricycle_calibration.h"
#include "support/tricycle_parameters.h"

namespace odometry_calibration {
namespace {

const TricycleEncoderLayout kLayout;

TricycleParameters truth()
{
  return test::simulatedTricycleTruth();
}

TricycleParameters nominal()
{
  return test::tricycleLogNominal();
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

/// The tracker's configuration of the cross-validation's fits, as calibrate_tricycle makes it.
CalibrationConfig trackerConfig()
{
  CalibrationConfig config;
  config.model = "tricycle";
  config.ego_motion = EgoMotionSource::kPose;
  config.models.joints.names = {"steering", "traction"};
  config.models.joints.kinds = {EncoderKind::kAbsolute, EncoderKind::kIncremental};
  config.models.tricycle.layout = kLayout;
  config.models.tricycle.initial = nominal();
  return config;
}

/// chooseFitInterval as calibrate_tricycle calls it: candidates at `candidates_s`, evaluation
/// pairs at the shortest, cuts into 2-6 blocks, the tracker's criterion.
FitIntervalChoice chooseForTracker(const SimulatedLog& log, const std::vector<double>& candidates_s,
                                   const std::vector<std::size_t>& fold_counts)
{
  std::vector<IntervalPairs> candidates;
  for (const double interval_s : candidates_s) {
    candidates.push_back({interval_s, referencePairs(log.samples, log.T_world_sensor, interval_s,
                                                     pairCovariance())});
  }
  FitIntervalOptions options;
  options.fold_counts = fold_counts;
  const CalibrationConfig config = trackerConfig();
  return chooseFitInterval(
      config, candidates,
      referencePairs(log.samples, log.T_world_sensor, candidates_s.front(), pairCovariance()),
      fitIntervalCriterion(config.ego_motion), options);
}

TEST(FitIntervalTracker, TheCriterionFollowsThePoseSource)
{
  EXPECT_EQ(fitIntervalCriterion(EgoMotionSource::kPose), FitIntervalCriterion::kAte);
  EXPECT_EQ(fitIntervalCriterion(EgoMotionSource::kScan), FitIntervalCriterion::kRpe);
  EXPECT_EQ(fitIntervalCriterion(EgoMotionSource::kCloud), FitIntervalCriterion::kRpe);
  EXPECT_EQ(fitIntervalCriterion(EgoMotionSource::kOdometry), FitIntervalCriterion::kRpe);
}

TEST(FitIntervalTracker, ACandidateLeavingAFoldTooFewPairsScoresInfinity)
{
  const SimulatedLog log = simulate(40.0, 0.0, 0.0, 3);
  // 8 s: 5 pairs in all, too few outside either half to fit the tricycle's seven parameters.
  const FitIntervalChoice choice = chooseForTracker(log, {0.5, 8.0}, {2});
  ASSERT_EQ(choice.curve.size(), 2u);
  EXPECT_EQ(choice.criterion, FitIntervalCriterion::kAte);
  EXPECT_TRUE(std::isfinite(choice.curve[0].validation_error_m));
  EXPECT_TRUE(std::isinf(choice.curve[1].validation_error_m));
  EXPECT_DOUBLE_EQ(choice.interval_s, 0.5);
  EXPECT_NE(formatFitIntervalChoice(choice, 0.5).find("validation ATE of 0.50 s pairs"),
            std::string::npos);
  EXPECT_THROW(chooseForTracker(log, {8.0}, {2}), std::invalid_argument);
}

TEST(FitIntervalTracker, ChoosesAnIntervalAsGoodAsTheBestOnUnseenData)
{
  const SimulatedLog log = simulate(300.0, 0.02, 0.0005, 5);
  const std::size_t split = log.samples.size() * 6 / 10;
  const SimulatedLog training = slice(log, 0, split);
  const SimulatedLog test = slice(log, split, log.samples.size());
  const std::vector<double> candidates_s = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
  const FitIntervalChoice choice = chooseForTracker(training, candidates_s, {2, 3, 4, 5, 6});
  ASSERT_EQ(choice.curve.size(), candidates_s.size());
  // The truth: each candidate's calibration error on the unseen 40 %. This drive's best interval
  // is 4 s; 0.25 s windows are 7x worse (the jitter's bias), 8 s 3x (the walk, few pairs).
  std::vector<double> error_m;
  for (const FitIntervalScore& score : choice.curve) {
    error_m.push_back(calibrationError(training, test, score.interval_s));
    std::printf("T %.2f s: validation %.4f m, calibration error on unseen data %.4f m\n",
                score.interval_s, score.validation_error_m, error_m.back());
  }
  const std::size_t best =
      static_cast<std::size_t>(std::min_element(error_m.begin(), error_m.end()) - error_m.begin());
  const std::size_t chosen = static_cast<std::size_t>(
      std::find(candidates_s.begin(), candidates_s.end(), choice.interval_s) -
      candidates_s.begin());
  ASSERT_LT(chosen, candidates_s.size());
  EXPECT_DOUBLE_EQ(candidates_s[best], 4.0);
  // Cross-validation on the training part alone lands next to it, far from the extremes.
  EXPECT_LE(chosen > best ? chosen - best : best - chosen, 1u) << choice.interval_s;
  EXPECT_LT(error_m[chosen], 1.5 * error_m[best]);
  EXPECT_LT(error_m[chosen], 0.25 * error_m.front());
  EXPECT_LT(error_m[chosen], 0.5 * error_m.back());
}

}  // namespace
}  // namespace odometry_calibration
