#include "odometry_calibration/data/encoder_glitch_filter.h"

#include <cmath>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

// A wheel (2000 ticks per turn, at most 10 turns/s, 32-bit counter) and a steering encoder.
EncoderGlitchFilter makeFilter()
{
  return EncoderGlitchFilter({{"wheel", EncoderKind::kIncremental, std::ldexp(1.0, 32), 0.0, 2e4},
                              {"steering", EncoderKind::kAbsolute, 0.0, 4096.0, 0.0}});
}

Eigen::VectorXd reading(double wheel, double steering = 100.0)
{
  return Eigen::Vector2d(wheel, steering);
}

TEST(EncoderGlitchFilter, PassesMotionWithinTheLimit)
{
  EncoderGlitchFilter filter = makeFilter();
  for (int k = 0; k < 100; ++k) {
    // 15 000 ticks/s: below the limit; the steering may jump (absolute: not checked).
    const auto result = filter.filter(0.01 * k, reading(150.0 * k, k % 2 ? 4000.0 : 10.0));
    ASSERT_FALSE(result.glitch) << k;
    EXPECT_EQ(result.corrected, reading(150.0 * k, k % 2 ? 4000.0 : 10.0));
  }
  // Stamps that jitter close together: a period's motion 0.1 ms after the last reading.
  EXPECT_FALSE(filter.filter(0.9901, reading(150.0 * 100)).glitch);
  // Before a speed is known (one reading), the rate limit alone: 0.1 s of motion at most.
  EncoderGlitchFilter fresh = makeFilter();
  EXPECT_FALSE(fresh.filter(0.0, reading(0.0)).glitch);
  EXPECT_FALSE(fresh.filter(0.0001, reading(2000.0)).glitch);
  EncoderGlitchFilter beyond = makeFilter();
  EXPECT_FALSE(beyond.filter(0.0, reading(0.0)).glitch);
  EXPECT_TRUE(beyond.filter(0.0001, reading(2001.0)).glitch);
}

TEST(EncoderGlitchFilter, SkipsASpikeAndGoesOn)
{
  EncoderGlitchFilter filter = makeFilter();
  EXPECT_FALSE(filter.filter(0.00, reading(1000.0)).glitch);
  EXPECT_FALSE(filter.filter(0.01, reading(1010.0)).glitch);
  const auto spike = filter.filter(0.02, reading(1e6 + 1020.0));
  EXPECT_TRUE(spike.glitch);
  EXPECT_EQ(spike.channel, 0u);
  EXPECT_NEAR(spike.increment, 1e6 + 10.0, 1e-6);
  EXPECT_EQ(spike.corrected.size(), 0);
  // The next sane reading is measured from the last accepted one: no motion lost or added.
  const auto next = filter.filter(0.03, reading(1030.0));
  ASSERT_FALSE(next.glitch);
  EXPECT_DOUBLE_EQ(next.corrected(0), 1030.0);
}

TEST(EncoderGlitchFilter, SkipsZerosBetweenTheReadingsWithinTheRateLimit)
{
  // A wheel 0.75 turns from 0, turning at 0.6 turns/s (1200 ticks/s), read at 50 Hz; then a
  // driver that sends a reading of 0 10 ms after each real one. Each step of 1500 ticks to 0
  // is within the 2000 ticks the rate limit allows over 0.1 s, yet 60 times the wheel's motion.
  EncoderGlitchFilter filter = makeFilter();
  double ticks = 1500.0;
  for (int k = 0; k < 60; ++k) {
    const double t = 0.02 * k;
    const auto real = filter.filter(t, reading(ticks));
    ASSERT_FALSE(real.glitch) << k;
    EXPECT_DOUBLE_EQ(real.corrected(0), ticks) << k;  // no offset: the counts went on
    EXPECT_EQ(real.continuous, k > 10) << k;          // after a skipped zero
    if (k >= 10) {
      const auto zero = filter.filter(t + 0.01, reading(0.0));
      EXPECT_TRUE(zero.glitch) << k;
      EXPECT_NEAR(zero.increment, -ticks, 1e-9) << k;
    }
    ticks += 24.0;
  }
}

TEST(EncoderGlitchFilter, SteadinessLeavesStartsBunchedStampsAndSlowEncodersAlone)
{
  EncoderGlitchFilter filter = makeFilter();
  // From rest, at once 1000 ticks/s (a simulated robot's step in speed), then doubling its
  // speed every 10 ms up to 8000 ticks/s, and turning back after a stop.
  double t = 0.0, ticks = 0.0;
  EXPECT_FALSE(filter.filter(t, reading(ticks)).glitch);
  EXPECT_FALSE(filter.filter(t += 0.01, reading(ticks)).glitch);
  for (double speed : {1000.0, 2000.0, 4000.0, 8000.0, 8000.0, 0.0, -1000.0, -2000.0}) {
    ticks += speed * 0.01;
    ASSERT_FALSE(filter.filter(t += 0.01, reading(ticks)).glitch) << speed;
  }
  // Two messages stamped 0.1 ms apart, the second with a whole period's motion.
  EXPECT_FALSE(filter.filter(t += 0.0001, reading(ticks -= 20.0)).glitch);
  EXPECT_FALSE(filter.filter(t += 0.01, reading(ticks -= 20.0)).glitch);
  // A 4 Hz encoder whose readings come 0.20 to 0.32 s apart, speeding up and slowing down.
  EncoderGlitchFilter slow = makeFilter();
  t = 0.0;
  ticks = 0.0;
  for (int k = 0; k < 40; ++k) {
    const double dt = k % 3 == 0 ? 0.32 : 0.20;
    t += dt;
    ticks += (k % 7 < 4 ? 4000.0 : 500.0) * dt;
    ASSERT_FALSE(slow.filter(t, reading(ticks)).glitch) << k;
  }
}

TEST(EncoderGlitchFilter, AHugeOrNonFiniteReadingNeverPasses)
{
  EncoderGlitchFilter filter = makeFilter();
  EXPECT_FALSE(filter.filter(0.0, reading(5.0)).glitch);
  EXPECT_TRUE(filter.filter(0.1, reading(1e300)).glitch);  // 1e300 mod 2^32 would be 0
  EXPECT_TRUE(filter.filter(0.1, reading(std::ldexp(1.0, 32) + 5.0)).glitch);  // out of range
  EXPECT_TRUE(filter.filter(0.2, reading(-1e300)).glitch);
  EXPECT_THROW(filter.filter(0.3, reading(std::nan(""))), std::invalid_argument);
  EXPECT_THROW(filter.filter(0.3, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  const auto sane = filter.filter(0.4, reading(6.0));
  ASSERT_FALSE(sane.glitch);
  EXPECT_DOUBLE_EQ(sane.corrected(0), 6.0);
}

TEST(EncoderGlitchFilter, ReanchorsWhenTheCounterJumpsAndStays)
{
  EncoderGlitchFilter filter = makeFilter();
  EXPECT_FALSE(filter.filter(0.00, reading(500.0)).glitch);
  EXPECT_TRUE(filter.filter(0.01, reading(7e6)).glitch);  // a driver restart, say
  // Consistent with the jumped value: the jump is absorbed, the count goes on from 500.
  const auto after = filter.filter(0.02, reading(7e6 + 20.0));
  ASSERT_FALSE(after.glitch);
  EXPECT_DOUBLE_EQ(after.corrected(0), 520.0);
  const auto later = filter.filter(0.03, reading(7e6 + 40.0));
  ASSERT_FALSE(later.glitch);
  EXPECT_DOUBLE_EQ(later.corrected(0), 540.0);
}

TEST(EncoderGlitchFilter, WrapAroundIsNotAGlitch)
{
  EncoderGlitchFilter filter = makeFilter();
  const double top = std::ldexp(1.0, 32);
  EXPECT_FALSE(filter.filter(0.00, reading(top - 50.0)).glitch);
  EXPECT_FALSE(filter.filter(0.01, reading(50.0)).glitch);
}

TEST(EncoderGlitchFilter, AnUndescribedCounterWrapIsNamed)
{
  // The same wheel without its counter size: a reading just across the 32-bit wrap (100 ticks
  // back) is a glitch whose step is a whole 2^32 give or take the motion possible in 0.1 s.
  EncoderGlitchFilter filter({{"wheel", EncoderKind::kIncremental, 0.0, 0.0, 2e4}});
  const double top = std::ldexp(1.0, 32);
  EXPECT_FALSE(filter.filter(0.0, Eigen::VectorXd::Constant(1, 50.0)).glitch);
  const auto wrapped = filter.filter(0.1, Eigen::VectorXd::Constant(1, top - 50.0));
  ASSERT_TRUE(wrapped.glitch);
  EXPECT_EQ(wrapped.wrap_bits, 32);
  // A driver restart to an arbitrary count is no wrap.
  EncoderGlitchFilter restart({{"wheel", EncoderKind::kIncremental, 0.0, 0.0, 2e4}});
  EXPECT_FALSE(restart.filter(0.0, Eigen::VectorXd::Constant(1, 50.0)).glitch);
  const auto jumped = restart.filter(0.1, Eigen::VectorXd::Constant(1, 7e6));
  ASSERT_TRUE(jumped.glitch);
  EXPECT_EQ(jumped.wrap_bits, 0);
  EXPECT_EQ(EncoderGlitchFilter::counterWrapBits(-65536.0 + 900.0, 1000.0), 16);
  EXPECT_EQ(EncoderGlitchFilter::counterWrapBits(-65536.0 + 1100.0, 1000.0), 0);
  EXPECT_EQ(EncoderGlitchFilter::counterWrapBits(256.0, 1000.0), 0);  // 8 bits: within motion
  EXPECT_EQ(EncoderGlitchFilter::counterWrapBits(1e308, 1000.0), 0);
  EXPECT_EQ(EncoderGlitchFilter::counterWrapBits(std::nan(""), 1000.0), 0);
}

TEST(EncoderGlitchFilter, TimeGoingBackwardsStartsOver)
{
  EncoderGlitchFilter filter = makeFilter();
  EXPECT_FALSE(filter.filter(10.0, reading(0.0)).glitch);
  EXPECT_FALSE(filter.filter(5.0, reading(9e8)).glitch);  // a looping bag
  EXPECT_FALSE(filter.filter(5.01, reading(9e8 + 10.0)).glitch);
}

// A steering encoder: absolute, 4096 counts per turn (readings above 2048 are negative), at
// most one turn per second.
EncoderGlitchFilter makeSteeringFilter()
{
  return EncoderGlitchFilter({{"steering", EncoderKind::kAbsolute, 0.0, 4096.0, 4096.0}});
}

Eigen::VectorXd steering(double counts)
{
  return Eigen::VectorXd::Constant(1, counts);
}

TEST(EncoderGlitchFilter, AbsoluteJointSpikeIsSkipped)
{
  EncoderGlitchFilter filter = makeSteeringFilter();
  EXPECT_FALSE(filter.filter(0.0, steering(100.0)).glitch);
  EXPECT_FALSE(filter.filter(0.1, steering(400.0)).glitch);  // 3000 counts/s: allowed
  const auto spike = filter.filter(0.2, steering(1e300));
  EXPECT_TRUE(spike.glitch);
  EXPECT_EQ(spike.channel, 0u);
  EXPECT_TRUE(filter.filter(0.3, steering(3000.0)).glitch);  // 2600 counts in 0.1 s: too fast
  // The next sane reading passes as it is (an absolute reading is never offset).
  const auto next = filter.filter(0.4, steering(500.0));
  ASSERT_FALSE(next.glitch);
  EXPECT_DOUBLE_EQ(next.corrected(0), 500.0);
}

TEST(EncoderGlitchFilter, AbsoluteJointWrapsAtItsFullRange)
{
  EncoderGlitchFilter filter = makeSteeringFilter();
  EXPECT_FALSE(filter.filter(0.00, steering(4090.0)).glitch);
  const auto across = filter.filter(0.01, steering(10.0));  // 16 counts through zero
  ASSERT_FALSE(across.glitch);
  EXPECT_DOUBLE_EQ(across.corrected(0), 10.0);
  EXPECT_TRUE(filter.filter(0.02, steering(4096.0 * 3)).glitch);  // beyond the range
}

TEST(EncoderGlitchFilter, AbsoluteJointThatJumpsAndStaysIsTakenAsItIs)
{
  EncoderGlitchFilter filter = makeSteeringFilter();
  EXPECT_FALSE(filter.filter(0.00, steering(0.0)).glitch);
  EXPECT_TRUE(filter.filter(0.01, steering(1500.0)).glitch);
  const auto after = filter.filter(0.02, steering(1510.0));
  ASSERT_FALSE(after.glitch);
  EXPECT_DOUBLE_EQ(after.corrected(0), 1510.0);  // where the joint is, no offset
}

TEST(EncoderGlitchFilter, ZeroRateChecksNothing)
{
  EncoderGlitchFilter filter({{"wheel", EncoderKind::kIncremental, 0.0, 0.0, 0.0}});
  EXPECT_FALSE(filter.filter(0.0, Eigen::VectorXd::Constant(1, 0.0)).glitch);
  EXPECT_FALSE(filter.filter(0.01, Eigen::VectorXd::Constant(1, 1e300)).glitch);
  EXPECT_THROW(EncoderGlitchFilter({{"wheel", EncoderKind::kIncremental, 0.0, 0.0, -1.0}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
