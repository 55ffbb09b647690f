#include <cmath>
#include <memory>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

constexpr double kRadius = 0.077;
constexpr double kCalibrationEndS = 300.0;  // the first 5 minutes are the calibration drive
constexpr double kChangeS = 600.0;          // the robot changes after 10 minutes

sim::PairGeneratorOptions run(double duration_s, unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", kRadius},
                    {"wheel_radius_right_m", kRadius},
                    {"wheel_separation_m", 0.33}}};
  options.T_base_sensor = Pose2(0.15, 0.02, 0.05);
  options.motion.max_speed_mps = 0.4;
  options.duration_s = duration_s;
  options.interval_s = 0.5;
  options.translation_noise_m = 0.002;
  options.rotation_noise_rad = 0.0015;
  options.seed = seed;
  return options;
}

/// Fits on the calibration drive, then monitors every later pair; returns the monitor.
std::unique_ptr<HealthMonitor> calibrateAndMonitor(const sim::GeneratedPairs& data,
                                                   HealthMonitorOptions options = {})
{
  std::vector<MotionPair> calibration;
  for (const MotionPair& pair : data.pairs) {
    if (pair.end_stamp_s <= kCalibrationEndS)
      calibration.push_back(pair);
  }
  DiffDriveOptions nominal;
  nominal.initial_left_radius_m = 0.075;
  nominal.initial_right_radius_m = 0.079;
  nominal.initial_separation_m = 0.32;
  nominal.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  auto model = std::make_shared<DiffDriveModel>(nominal);
  const ModelReport report = model->fit(calibration);
  EXPECT_TRUE(report.converged) << report.termination;
  auto monitor = std::make_unique<HealthMonitor>(model, options);
  for (const MotionPair& pair : data.pairs) {
    if (pair.start_stamp_s >= kCalibrationEndS && monitor->addPair(pair))
      break;  // the first alarm is what the tests look at
  }
  return monitor;
}

TEST(HealthMonitor, RightWheelShrinkingOnePercentIsFoundWithinTwoMinutesAndNamed)
{
  sim::PairGeneratorOptions options = run(1200.0, 5);
  sim::ParameterChange change;
  change.at_s = kChangeS;
  change.robot_parameters["wheel_radius_right_m"] = 0.99 * kRadius;
  options.changes = {change};
  const auto monitor = calibrateAndMonitor(sim::generatePairs(options));
  const HealthStatus status = monitor->status();
  ASSERT_TRUE(status.alarm) << status.message;
  EXPECT_GT(status.alarm_stamp_s, kChangeS) << status.message;
  EXPECT_LT(status.alarm_stamp_s, kChangeS + 120.0) << status.message;
  EXPECT_EQ(status.alarm_output, "theta") << status.message;
  EXPECT_TRUE(status.message.find("radius") != std::string::npos ||
              status.message.find("rotation") != std::string::npos)
      << status.message;
  EXPECT_NE(status.message.find("refit"), std::string::npos);
  EXPECT_GE(status.statistic, 1.0);
  std::printf("right wheel -1 %%: alarm %.1f s after the change: %s\n",
              status.alarm_stamp_s - kChangeS, status.message.c_str());
}

TEST(HealthMonitor, LaserYawedOneDegreeIsFoundAndNamed)
{
  sim::PairGeneratorOptions options = run(1200.0, 6);
  sim::ParameterChange change;
  change.at_s = kChangeS;
  change.laser_yaw_change_rad = M_PI / 180.0;
  options.changes = {change};
  const auto monitor = calibrateAndMonitor(sim::generatePairs(options));
  const HealthStatus status = monitor->status();
  ASSERT_TRUE(status.alarm) << status.message;
  EXPECT_GT(status.alarm_stamp_s, kChangeS) << status.message;
  EXPECT_LT(status.alarm_stamp_s, kChangeS + 120.0) << status.message;
  EXPECT_EQ(status.alarm_output, "y") << status.message;
  EXPECT_NE(status.message.find("yaw"), std::string::npos) << status.message;
  std::printf("laser yawed 1 deg: alarm %.1f s after the change: %s\n",
              status.alarm_stamp_s - kChangeS, status.message.c_str());
}

TEST(HealthMonitor, UnchangedRobotRaisesNoAlarmInAnHour)
{
  const auto monitor = calibrateAndMonitor(sim::generatePairs(run(3600.0, 7)));
  const HealthStatus status = monitor->status();
  EXPECT_FALSE(status.alarm) << status.message;
  EXPECT_GT(status.pairs, 6000u);
  EXPECT_LT(status.statistic, 1.0);
  for (const HealthChart& chart : status.charts) {
    EXPECT_TRUE(chart.calibrated) << chart.name;
    EXPECT_GT(chart.count, 200u) << chart.name;
  }
  std::printf("unchanged, 55 min monitored: largest statistic %.2f\n", status.statistic);
}

/// Predicts a fixed straight run of 0.2 m with 2 mm / 2 mrad of covariance.
class StraightModel : public MotionModel
{
public:
  std::string name() const override { return "straight"; }
  ModelReport fit(const std::vector<MotionPair>&) override { return {}; }
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override
  {
    if (samples.size() < 2)
      throw std::invalid_argument("need two samples");
    MotionPrediction prediction;
    prediction.mean = Pose2(0.2, 0.0, 0.0);
    prediction.covariance.diagonal() << 4e-6, 4e-6, 4e-6;
    return prediction;
  }
  std::string toYaml() const override { return ""; }
};

std::vector<MotionPair> straightPairs(double travel_factor, int count, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<MotionPair> pairs;
  for (int i = 0; i < count; ++i) {
    MotionPair pair;
    pair.start_stamp_s = i;
    pair.end_stamp_s = i + 1;
    pair.encoder_samples.resize(2);
    pair.sensor_motion = Pose2(0.2 * travel_factor + noise(rng), noise(rng), noise(rng));
    pair.covariance.diagonal() << 4e-6, 4e-6, 4e-6;
    pairs.push_back(pair);
  }
  return pairs;
}

TEST(HealthMonitor, ShortTravelIsNamedAsShrunkRadii)
{
  HealthMonitor monitor(std::make_shared<StraightModel>(), HealthMonitorOptions());
  int raised_at = -1;
  const auto before = straightPairs(1.0, 300, 1);
  const auto after = straightPairs(0.98, 300, 2);  // travel 2 % (4 mm, 1.4 sigma) short
  for (const auto& pair : before)
    EXPECT_FALSE(monitor.addPair(pair));
  for (std::size_t i = 0; i < after.size() && raised_at < 0; ++i) {
    if (monitor.addPair(after[i]))
      raised_at = static_cast<int>(i);
  }
  const HealthStatus status = monitor.status();
  ASSERT_TRUE(status.alarm);
  EXPECT_GE(raised_at, 3);  // a sustained shift, not one pair
  EXPECT_LT(raised_at, 60);
  EXPECT_EQ(status.alarm_output, "x");
  EXPECT_NE(status.message.find("travel reads short"), std::string::npos) << status.message;
}

TEST(HealthMonitor, OneGrossOutlierDoesNotRaiseTheAlarm)
{
  HealthMonitor monitor(std::make_shared<StraightModel>(), HealthMonitorOptions());
  auto pairs = straightPairs(1.0, 400, 3);
  pairs[250].sensor_motion = Pose2(1.0, 0.5, 0.3);  // a failed scan match
  for (const auto& pair : pairs)
    EXPECT_FALSE(monitor.addPair(pair));
  EXPECT_FALSE(monitor.status().alarm);
}

TEST(HealthMonitor, SkipsPairsTheModelCannotPredict)
{
  HealthMonitor monitor(std::make_shared<StraightModel>(), HealthMonitorOptions());
  MotionPair pair;  // no samples
  EXPECT_FALSE(monitor.addPair(pair));
  EXPECT_EQ(monitor.skipped(), 1u);
  EXPECT_EQ(monitor.status().pairs, 0u);
  EXPECT_NE(monitor.status().message.find("ok"), std::string::npos);
}

TEST(HealthMonitor, ThresholdMatchesSiegmundsApproximation)
{
  // Siegmund: k = 0.5, h = 4 gives ARL0 = (e^5.166 - 5.166 - 1) / 0.5 = 338.
  EXPECT_NEAR(cusumThreshold(0.5, 338.1), 4.0, 0.01);
  // A rarer false alarm needs a higher threshold.
  EXPECT_GT(cusumThreshold(0.5, 1e6), cusumThreshold(0.5, 1e4));
  EXPECT_THROW(cusumThreshold(0.0, 100.0), std::invalid_argument);
}

TEST(HealthMonitor, RejectsBadOptionsAndNoModel)
{
  HealthMonitorOptions options;
  options.false_alarm_pairs = 1.0;
  EXPECT_THROW(HealthMonitor(std::make_shared<StraightModel>(), options), std::invalid_argument);
  EXPECT_THROW(HealthMonitor(nullptr, HealthMonitorOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
