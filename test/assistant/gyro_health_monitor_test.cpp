// The gyro's health monitor on a simulated drive: a laser's pairs (rotation with 2 mrad of noise,
// one every 0.5 s) and a 100 Hz gyro (scale 1.015, bias 0.01 rad/s walking 3e-6 rad/s/sqrt(s), three times the shipped gyro scenario's, 5 mrad/s
// of noise, a clock 20 ms late), the gyro's scale raised by 1 % mid-run in some runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "odometry_calibration/assistant/gyro_health_monitor.h"

namespace odometry_calibration {
namespace {

constexpr double kScale = 1.015, kBias = 0.01, kShift = 0.02;

struct Drive
{
  std::vector<std::pair<double, double>> readings;  ///< (gyro stamp, yaw rate reading)
  std::vector<MotionPair> pairs;
};

struct GyroChange
{
  double at_s = 1e9;            ///< from this instant on
  double scale_factor = 1.0;    ///< the scale is multiplied by this
  double bias_step_rad_s = 0.0;  ///< the bias grows by this
};

/// Turns left, straight, right at random lengths, the yaw rate following its target with 0.3 s
/// of lag; truth integrated at 1 kHz.
Drive simulate(double duration_s, unsigned seed, const GyroChange& change)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> length(1.5, 4.0);
  const double step = 0.001;
  Drive drive;
  double rate = 0.0, heading = 0.0, bias_walk = 0.0, target = 0.0, segment_end = 0.0;
  double pair_start_heading = 0.0, pair_start = 0.0;
  int segment = 0;
  for (int i = 0; i * step < duration_s; ++i) {
    const double t = i * step;
    if (t >= segment_end) {
      const double targets[4] = {0.6, 0.0, -0.6, 0.0};
      target = targets[segment++ % 4];
      segment_end = t + length(rng);
    }
    if (i % 10 == 0) {  // the 100 Hz gyro, stamped on its own clock
      const bool changed = t >= change.at_s;
      const double scale = kScale * (changed ? change.scale_factor : 1.0);
      const double bias = kBias + bias_walk + (changed ? change.bias_step_rad_s : 0.0);
      drive.readings.emplace_back(t + kShift, scale * rate + bias + 0.005 * normal(rng));
      bias_walk += 3e-6 * std::sqrt(0.01) * normal(rng);
    }
    if (i % 500 == 0 && i > 0) {  // a keyframe pair every 0.5 s
      MotionPair pair;
      pair.start_stamp_s = pair_start;
      pair.end_stamp_s = t;
      pair.sensor_motion = Pose2(0.1, 0.0, heading - pair_start_heading + 0.002 * normal(rng));
      drive.pairs.push_back(pair);
      pair_start = t;
      pair_start_heading = heading;
    }
    rate += (target - rate) * step / 0.3;
    heading += rate * step;
  }
  return drive;
}

/// Feeds the drive in time order (a pair when its end has passed) to a monitor of a calibration
/// 0.05 % off in scale and 5e-5 rad/s off in bias (the fit's error).
GyroHealthStatus monitor(const Drive& drive)
{
  GyroHealthMonitor health({kScale * 1.0005, kBias + 5e-5, kShift}, GyroHealthOptions{});
  std::size_t next_pair = 0;
  for (const auto& [stamp, rate] : drive.readings) {
    while (next_pair < drive.pairs.size() && drive.pairs[next_pair].end_stamp_s <= stamp)
      health.addPair(drive.pairs[next_pair++]);
    EXPECT_EQ(health.addReading(stamp, rate), "");
  }
  return health.status();
}

TEST(GyroHealthMonitor, NamesAOnePercentScaleChangeWithin30Seconds)
{
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const double change_s = 300.0;
    const GyroHealthStatus status = monitor(simulate(420.0, seed, {change_s, 1.01, 0.0}));
    ASSERT_TRUE(status.alarm) << "seed " << seed << ": " << status.message;
    EXPECT_EQ(status.cause, "gyro scale") << status.message;
    EXPECT_GE(status.alarm_stamp_s, change_s) << status.message;
    EXPECT_LE(status.alarm_stamp_s, change_s + 30.0) << status.message;
    EXPECT_NEAR(status.scale_now, kScale * 1.01, 0.002) << status.message;
    EXPECT_NEAR(status.bias_now_rad_s, kBias, 0.002) << status.message;
    std::printf("seed %u: alarm %.1f s after the change; %s\n", seed,
                status.alarm_stamp_s - change_s, status.message.c_str());
  }
}

TEST(GyroHealthMonitor, UnchangedRunsRaiseNoAlarm)
{
  for (unsigned seed = 101; seed <= 120; ++seed) {
    const GyroHealthStatus status = monitor(simulate(1200.0, seed, {}));
    EXPECT_FALSE(status.alarm) << "seed " << seed << ": " << status.message;
    EXPECT_LT(status.statistic, 1.0);
    EXPECT_GT(status.pairs, 2300u);
    EXPECT_EQ(status.skipped, 0u);
    for (const GyroHealthChart& chart : status.charts)
      EXPECT_TRUE(chart.calibrated) << chart.name;
    std::printf("seed %u, 20 min unchanged: largest statistic %.2f\n", seed, status.statistic);
  }
}

TEST(GyroHealthMonitor, NamesABiasChangeAsTheBias)
{
  const GyroHealthStatus status = monitor(simulate(420.0, 21, {300.0, 1.0, 0.005}));
  ASSERT_TRUE(status.alarm) << status.message;
  EXPECT_EQ(status.cause, "gyro bias") << status.message;
  EXPECT_LE(status.alarm_stamp_s, 360.0) << status.message;
  EXPECT_NEAR(status.bias_now_rad_s, kBias + 0.005, 0.0015) << status.message;
  EXPECT_NEAR(status.scale_now, kScale, 0.003) << status.message;
}

TEST(GyroHealthMonitor, RefusesBadReadingsAndCalibrations)
{
  GyroHealthMonitor health({kScale, kBias, kShift}, GyroHealthOptions{});
  EXPECT_NE(health.addReading(1.0, std::nan("")), "");
  EXPECT_EQ(health.addReading(1.0, 0.1), "");
  EXPECT_NE(health.addReading(0.5, 0.1).find("not after the last"), std::string::npos);
  EXPECT_NE(health.addReading(1.01, 1e308 * 10.0), "");
  EXPECT_THROW(GyroHealthMonitor({0.0, 0.0, 0.0}, GyroHealthOptions{}), std::invalid_argument);
  EXPECT_THROW(GyroHealthMonitor({1.0, std::nan(""), 0.0}, GyroHealthOptions{}),
               std::invalid_argument);
  GyroHealthOptions options;
  options.burn_in_pairs = 3;
  EXPECT_THROW(GyroHealthMonitor({1.0, 0.0, 0.0}, options), std::invalid_argument);
  // A pair whose interval lies before the readings kept cannot be scored: skipped, no alarm.
  MotionPair early;
  early.start_stamp_s = 0.0;
  early.end_stamp_s = 0.5;
  early.sensor_motion = Pose2(0.1, 0.0, 0.3);
  EXPECT_FALSE(health.addPair(early));
  EXPECT_EQ(health.status().skipped, 1u);
  EXPECT_EQ(health.status().pairs, 0u);
}

}  // namespace
}  // namespace odometry_calibration
