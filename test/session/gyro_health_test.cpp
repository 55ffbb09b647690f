// The session's watch of its calibrated gyro (gyro_health.h) on a simulated drive
// (support/gyro_drive.h): nothing before a fit is watched, one warning naming the gyro's scale
// after a 1 % change, the "gyro health" status at warn; an unfitted fit stops the watch.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "odometry_calibration/session/gyro_health.h"
#include "support/gyro_drive.h"

namespace odometry_calibration {
namespace {

void feed(GyroHealth& health, const test::Drive& drive)
{
  std::size_t next_pair = 0;
  for (const auto& [stamp, rate] : drive.readings) {
    while (next_pair < drive.pairs.size() && drive.pairs[next_pair].end_stamp_s <= stamp)
      health.addPair(drive.pairs[next_pair++]);
    health.addReading(stamp, rate);
  }
}

GyroFit fitted(double scale, double bias_rad_s, double shift_s)
{
  GyroFit fit;
  fit.fitted = true;
  fit.scale.value = scale;
  fit.bias.value = bias_rad_s;
  fit.shift_s = shift_s;
  return fit;
}

TEST(GyroHealth, WarnsOnceNamingTheScaleAfterItsChange)
{
  std::vector<std::string> warnings;
  GyroHealth health([&](SessionLogLevel level, const std::string& text) {
    if (level == SessionLogLevel::kWarn)
      warnings.push_back(text);
  });
  const test::Drive drive = test::simulateGyroDrive(400.0, 3, {300.0, 1.01, 0.0});
  feed(health, drive);  // no fit watched yet: nothing scored, no status
  EXPECT_FALSE(health.status().has_value());

  health.watch(fitted(test::kScale, test::kBias, test::kShift));
  feed(health, drive);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("gyro health: gyro scale drifted", 0), 0u) << warnings[0];
  const std::optional<SessionStatusReport> status = health.status();
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->name, "gyro health");
  EXPECT_EQ(status->level, SessionStatusReport::Level::kWarn);
  EXPECT_NE(status->message.find("refit (call ~calibrate)"), std::string::npos);

  health.watch(GyroFit{});  // a fit that is not fitted: no watch
  EXPECT_FALSE(health.status().has_value());
  health.watch(fitted(test::kScale, test::kBias, test::kShift));
  feed(health, test::simulateGyroDrive(200.0, 4, {}));
  ASSERT_TRUE(health.status().has_value());
  EXPECT_EQ(health.status()->level, SessionStatusReport::Level::kOk) << health.status()->message;
  EXPECT_EQ(warnings.size(), 1u);
  health.clear();
  EXPECT_FALSE(health.status().has_value());
}

}  // namespace
}  // namespace odometry_calibration
