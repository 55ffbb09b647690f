#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/data/encoder.h"

namespace odometry_calibration {
namespace {

constexpr double kUint32 = 4294967296.0;

TEST(WrappedDifference, PlainWithoutWrapPeriod)
{
  EXPECT_DOUBLE_EQ(wrappedDifference(100.0, 250.0, 0.0), 150.0);
  EXPECT_DOUBLE_EQ(wrappedDifference(250.0, 100.0, 0.0), -150.0);
}

TEST(WrappedDifference, Uint32OverflowOfTheRealDataset)
{
  // shared/data/tricycle: samples 58 -> 59, the counter overflows: +4987 ticks.
  EXPECT_EQ(wrappedDifference(4294962835.0, 526.0, kUint32), 4987.0);
}

TEST(WrappedDifference, ReversalIsANegativeStepNotAnOverflow)
{
  EXPECT_EQ(wrappedDifference(5543456.0, 5540000.0, kUint32), -3456.0);
  // Reversing across the wrap: 10 -> 2^32 - 20 is 30 ticks backwards.
  EXPECT_EQ(wrappedDifference(10.0, kUint32 - 20.0, kUint32), -30.0);
}

TEST(WrappedDifference, SmallCounterWidthAndAngles)
{
  // A 16-bit counter.
  EXPECT_EQ(wrappedDifference(65530.0, 4.0, 65536.0), 10.0);
  // A joint angle that wraps at 2 pi.
  EXPECT_NEAR(wrappedDifference(3.1, -3.1, 2.0 * M_PI), 2.0 * M_PI - 6.2, 1e-12);
}

TEST(SignedAbsoluteReading, UpperHalfIsNegative)
{
  EXPECT_EQ(signedAbsoluteReading(290.0, 8192.0), 290.0);
  EXPECT_EQ(signedAbsoluteReading(8156.0, 8192.0), -36.0);
  EXPECT_EQ(signedAbsoluteReading(4096.0, 8192.0), 4096.0);
  EXPECT_EQ(signedAbsoluteReading(4097.0, 8192.0), -4095.0);
  EXPECT_EQ(signedAbsoluteReading(8156.0, 0.0), 8156.0);
}

TEST(EncoderDecoder, DecodesAMixedSequenceWithWrapAndReversal)
{
  EncoderDecoder decoder({{"steering", EncoderKind::kAbsolute, 0.0, 8192.0},
                          {"traction", EncoderKind::kIncremental, kUint32, 0.0}});
  const double raw[][2] = {{290, 4294962000.0}, {8100, 4294962835.0}, {10, 526.0}, {10, 100.0}};
  const double expected[][2] = {{290, 0}, {-92, 835}, {10, 835 + 4987}, {10, 835 + 4987 - 426}};
  for (int i = 0; i < 4; ++i) {
    const Eigen::VectorXd decoded = decoder.decode(Eigen::Vector2d(raw[i][0], raw[i][1]));
    EXPECT_EQ(decoded(0), expected[i][0]) << "sample " << i;
    EXPECT_EQ(decoded(1), expected[i][1]) << "sample " << i;
  }
  decoder.reset();
  EXPECT_EQ(decoder.decode(Eigen::Vector2d(0.0, 1000.0))(1), 0.0);
  EXPECT_EQ(decoder.decode(Eigen::Vector2d(0.0, 1200.0))(1), 200.0);
}

TEST(EncoderDecoder, RejectsBadReadingsWithAClearMessage)
{
  EncoderDecoder decoder({{"left_wheel", EncoderKind::kIncremental, 0.0, 0.0}});
  EXPECT_THROW(decoder.decode(Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  try {
    decoder.decode(Eigen::VectorXd::Constant(1, std::nan("")));
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("left_wheel"), std::string::npos);
  }
}

TEST(EncoderDecoder, RejectsInvalidOptions)
{
  EXPECT_THROW(EncoderDecoder({{"w", EncoderKind::kIncremental, -1.0, 0.0}}),
               std::invalid_argument);
  EXPECT_THROW(EncoderDecoder({{"s", EncoderKind::kAbsolute, 0.0, std::nan("")}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
