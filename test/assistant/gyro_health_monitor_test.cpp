// The gyro's health monitor on a simulated drive (support/gyro_drive.h), the gyro's scale raised
// by 1 % mid-run in some runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "odometry_calibration/assistant/gyro_health_monitor.h"
#include "support/gyro_drive.h"

namespace odometry_calibration {
namespace {

using test::Drive;
using test::GyroChange;
using test::kBias;
using test::kScale;
using test::kShift;

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
    const GyroHealthStatus status =
        monitor(test::simulateGyroDrive(420.0, seed, {change_s, 1.01, 0.0}));
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
    const GyroHealthStatus status = monitor(test::simulateGyroDrive(1200.0, seed, {}));
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
  const GyroHealthStatus status = monitor(test::simulateGyroDrive(420.0, 21, {300.0, 1.0, 0.005}));
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
