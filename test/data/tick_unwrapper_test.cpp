#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/data/tick_unwrapper.h"

namespace odometry_calibration {
namespace {

/// The text of what `call` throws (std::invalid_argument), or "" when it does not throw.
template <class Call>
std::string refusal(Call call)
{
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(TickUnwrapper, EightBitCounterInAnInt16CountsOnAcrossItsWraps)
{
  // 40 ticks per message forward, as an 8-bit counter carried unsigned (0..255) in an Int16.
  TickUnwrapper unwrapper(8, "joints[0].counter_bits", "'left'");
  double raw = 200.0;
  EXPECT_EQ(unwrapper.unwrap(0.0, raw), 0.0);
  for (int k = 1; k <= 20; ++k) {
    raw = static_cast<double>((200 + 40 * k) % 256);
    EXPECT_EQ(unwrapper.unwrap(0.02 * k, raw), 40.0 * k) << k;
  }
}

TEST(TickUnwrapper, SignExtendedEightBitCounterAndReversal)
{
  // The same counter sign-extended into the Int16 (-128..127): 120 -> -126 is +10 ticks,
  // then back across the wrap: -126 -> 125 is -5 ticks.
  TickUnwrapper unwrapper(8, "joints[1].counter_bits", "'right'");
  unwrapper.unwrap(0.0, 110.0);
  EXPECT_EQ(unwrapper.unwrap(0.02, 120.0), 10.0);
  EXPECT_EQ(unwrapper.unwrap(0.04, -126.0), 20.0);
  EXPECT_EQ(unwrapper.unwrap(0.06, 125.0), 15.0);
}

TEST(TickUnwrapper, SixteenBitCounter)
{
  TickUnwrapper unwrapper(16, "joints[0].counter_bits", "'left'");
  unwrapper.unwrap(0.0, 65500.0);
  EXPECT_EQ(unwrapper.unwrap(0.02, 70.0), 106.0);
  EXPECT_EQ(unwrapper.unwrap(0.04, 65530.0), 30.0);  // 76 ticks back across the wrap
}

TEST(TickUnwrapper, AliasingIsRefusedNamingTheKeyTheMeasuredStepAndTheFix)
{
  // Speeding up by 30 ticks per message on an 8-bit counter: steps 70, 100, 130 (> 128 reads
  // as -126, aliased).
  TickUnwrapper unwrapper(8, "joints[0].counter_bits", "'left' on '/lwheel'");
  unwrapper.unwrap(0.00, 0.0);
  EXPECT_EQ(unwrapper.unwrap(0.03, 70.0), 70.0);
  EXPECT_EQ(unwrapper.unwrap(0.06, 170.0), 170.0);
  const std::string text = refusal([&] { unwrapper.unwrap(0.09, 44.0); });  // 170 + 130
  EXPECT_NE(text.find("aliases"), std::string::npos) << text;
  EXPECT_NE(text.find("joints[0].counter_bits 8 (256 ticks)"), std::string::npos) << text;
  EXPECT_NE(text.find("'left' on '/lwheel'"), std::string::npos) << text;
  EXPECT_NE(text.find("the previous message's step was 100 ticks"), std::string::npos) << text;
  EXPECT_NE(text.find("reads -126"), std::string::npos) << text;  // the aliased step
  EXPECT_NE(text.find("publish the ticks faster"), std::string::npos) << text;
  // The wheel stays refused: a count that skipped a wrap would be wrong in every later pair.
  const std::string later = refusal([&] { unwrapper.unwrap(0.12, 50.0); });
  EXPECT_NE(later.find("refused since an earlier reading"), std::string::npos) << later;
}

TEST(TickUnwrapper, BunchedAndStalledReceiveTimesAreNotAliasing)
{
  // 100 ticks per message on an 8-bit counter, the messages received in bursts: 1 ms apart, then
  // a 0.3 s stall (a speed of 100 ticks / 1 ms would predict 30000 ticks across it).
  TickUnwrapper unwrapper(8, "joints[0].counter_bits", "'left'");
  const double stamps[] = {0.0, 0.001, 0.002, 0.302, 0.303, 0.304};
  for (int k = 0; k < 6; ++k)
    EXPECT_EQ(unwrapper.unwrap(stamps[k], (100 * k) % 256), 100.0 * k) << k;
}

TEST(TickUnwrapper, AStopAndReverseIsNotAliasing)
{
  TickUnwrapper unwrapper(8, "joints[0].counter_bits", "'left'");
  unwrapper.unwrap(0.0, 0.0);
  EXPECT_EQ(unwrapper.unwrap(0.02, 100.0), 100.0);
  EXPECT_EQ(unwrapper.unwrap(0.04, 210.0), 210.0);
  EXPECT_EQ(unwrapper.unwrap(0.06, 210.0), 210.0);  // stopped: 110 ticks below the prediction
  EXPECT_EQ(unwrapper.unwrap(0.08, 150.0), 150.0);  // reversing
}

TEST(TickUnwrapper, ValuesBeyondTheCounterAndNonFiniteAreRefused)
{
  TickUnwrapper unwrapper(8, "joints[0].counter_bits", "'left'");
  const std::string wide = refusal([&] { unwrapper.unwrap(0.0, 1000.0); });
  EXPECT_NE(wide.find("reading 1000 does not fit joints[0].counter_bits 8"), std::string::npos)
      << wide;
  EXPECT_NE(refusal([&] { unwrapper.unwrap(0.0, std::nan("")); }).find("not finite"),
            std::string::npos);
  TickUnwrapper unbounded(0, "joints[0].counter_bits", "'left'");
  EXPECT_NE(refusal([&] { unbounded.unwrap(0.0, 1e308); }).find("below 2^53"), std::string::npos);
  EXPECT_EQ(unbounded.unwrap(0.0, 5.0), 0.0);
  EXPECT_EQ(unbounded.unwrap(0.1, 1e6), 1e6 - 5.0);
  EXPECT_THROW(TickUnwrapper(53, "joints[0].counter_bits", "'left'"), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
