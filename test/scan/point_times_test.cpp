// Per-point lidar times into seconds after the cloud's stamp: the drivers' conventions (relative
// seconds, relative nanoseconds, absolute seconds, absolute nanoseconds) told apart by type and
// value, the overrides, and the times that cannot be right (the cloud's times are then refused).
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/point_times.h"

namespace odometry_calibration {
namespace {

constexpr double kStamp = 1700000123.25;  // a header stamp [s since the epoch]

/// 0, 1 ms, ..., 99 ms: a 10 Hz sweep's times after its stamp [s].
std::vector<double> sweep()
{
  std::vector<double> t;
  for (int i = 0; i < 100; ++i)
    t.push_back(1e-3 * i);
  return t;
}

/// `values` converted with the default (auto) options.
PointTimeConversion convert(std::vector<double>& values, bool integer_field,
                            const PointTimeOptions& options = {})
{
  return toTimesAfterStamp(values, integer_field, kStamp, options);
}

void expectSweep(const std::vector<double>& values, double tolerance)
{
  const auto truth = sweep();
  ASSERT_EQ(values.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    EXPECT_NEAR(values[i], truth[i], tolerance) << "point " << i;
}

TEST(PointTimes, VelodyneRelativeSecondsStayAsTheyAre)
{
  auto values = sweep();
  const auto conversion = convert(values, false);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_EQ(conversion.unit, PointTimeUnit::kSeconds);
  EXPECT_EQ(conversion.reference, PointTimeReference::kRelative);
  expectSweep(values, 1e-15);
}

TEST(PointTimes, OusterIntegerNanosecondsBecomeSeconds)
{
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(std::round(t * 1e9));
  const auto conversion = convert(values, true);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_EQ(conversion.unit, PointTimeUnit::kNanoseconds);
  EXPECT_EQ(conversion.reference, PointTimeReference::kRelative);
  expectSweep(values, 1e-12);
}

TEST(PointTimes, HesaiAbsoluteSecondsBecomeTimesAfterTheStamp)
{
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(kStamp + t);
  const auto conversion = convert(values, false);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_EQ(conversion.unit, PointTimeUnit::kSeconds);
  EXPECT_EQ(conversion.reference, PointTimeReference::kAbsolute);
  expectSweep(values, 1e-6);  // a double near 1.7e9 s resolves 0.24 us
}

TEST(PointTimes, LivoxAbsoluteFloatingNanosecondsBecomeTimesAfterTheStamp)
{
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back((kStamp + t) * 1e9);
  const auto conversion = convert(values, false);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_EQ(conversion.unit, PointTimeUnit::kNanoseconds);
  EXPECT_EQ(conversion.reference, PointTimeReference::kAbsolute);
  expectSweep(values, 1e-6);
}

TEST(PointTimes, StampedAtTheSweepsEndNegativeTimesAreUsable)
{
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(kStamp - 0.1 + t);  // the stamp is the sweep's last point's time
  const auto conversion = convert(values, false);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_NEAR(values.front(), -0.1, 1e-6);
  EXPECT_NEAR(values.back(), -0.001, 1e-6);
}

TEST(PointTimes, TheConfiguredUnitAndReferenceOverrideTheGuess)
{
  // Microseconds in a float field: the guess (seconds) would read 99000 s.
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(t * 1e6);
  std::vector<double> guessed = values;
  EXPECT_FALSE(convert(guessed, false).usable());
  PointTimeOptions options;
  options.unit = pointTimeUnitName("us");
  const auto conversion = convert(values, false, options);
  EXPECT_TRUE(conversion.usable()) << conversion.problem;
  EXPECT_EQ(conversion.unit, PointTimeUnit::kMicroseconds);
  expectSweep(values, 1e-12);

  // Absolute seconds declared relative: 1.7e9 s after the stamp, refused, never used.
  values.clear();
  for (const double t : sweep())
    values.push_back(kStamp + t);
  options = PointTimeOptions();
  options.reference = pointTimeReferenceName("relative");
  const auto wrong = convert(values, false, options);
  EXPECT_FALSE(wrong.usable());
  EXPECT_NE(wrong.problem.find("read as relative s"), std::string::npos) << wrong.problem;
}

TEST(PointTimes, ANanTimeMakesTheCloudsTimesUnusable)
{
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(kStamp + t);
  values[37] = std::numeric_limits<double>::quiet_NaN();
  const auto conversion = convert(values, false);
  EXPECT_FALSE(conversion.usable());
  EXPECT_NE(conversion.problem.find("point 37's time is nan"), std::string::npos)
      << conversion.problem;
  // The median still tells the reference: absolute.
  EXPECT_EQ(conversion.reference, PointTimeReference::kAbsolute);
}

TEST(PointTimes, TimesFarOutsideTheSweepMakeTheCloudsTimesUnusable)
{
  // One point stamped with another cloud's time, 2 s later.
  std::vector<double> values;
  for (const double t : sweep())
    values.push_back(kStamp + t);
  values[80] += 2.0;
  auto conversion = convert(values, false);
  EXPECT_FALSE(conversion.usable());
  EXPECT_NE(conversion.problem.find("point 80's time is 2.08"), std::string::npos)
      << conversion.problem;
  EXPECT_NE(conversion.problem.find("beyond the 0.5 s"), std::string::npos) << conversion.problem;

  // Every absolute time belongs to a cloud 0.7 s earlier: beyond the default limit, within 1 s.
  values.clear();
  for (const double t : sweep())
    values.push_back(kStamp - 0.7 + t);
  std::vector<double> copy = values;
  EXPECT_FALSE(convert(copy, false).usable());
  PointTimeOptions options;
  options.limit_s = 1.0;
  EXPECT_TRUE(convert(values, false, options).usable());
  EXPECT_NEAR(values[0], -0.7, 1e-6);
}

TEST(PointTimes, NoValuesAreUsable)
{
  std::vector<double> values;
  EXPECT_TRUE(convert(values, true).usable());
}

TEST(PointTimes, NamesAndBadOptionsAreChecked)
{
  EXPECT_EQ(pointTimeUnitName("ns"), PointTimeUnit::kNanoseconds);
  EXPECT_EQ(pointTimeUnitName("auto"), PointTimeUnit::kAuto);
  EXPECT_EQ(pointTimeReferenceName("absolute"), PointTimeReference::kAbsolute);
  EXPECT_STREQ(toString(PointTimeUnit::kMilliseconds), "ms");
  EXPECT_THROW(pointTimeUnitName("seconds"), std::invalid_argument);
  EXPECT_THROW(pointTimeReferenceName("epoch"), std::invalid_argument);
  PointTimeOptions options;
  EXPECT_NO_THROW(validate(options));
  options.limit_s = 0.0;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options.limit_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validate(options), std::invalid_argument);
  EXPECT_EQ(defaultPointTimeFields(), (std::vector<std::string>{"time", "t", "timestamp"}));
}

}  // namespace
}  // namespace odometry_calibration
