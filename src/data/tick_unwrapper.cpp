#include "odometry_calibration/data/tick_unwrapper.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "odometry_calibration/data/encoder.h"

namespace odometry_calibration {
namespace {

constexpr double kExactTicks = 9007199254740992.0;  // 2^53: the doubles' exact integers

std::string number(double value)
{
  std::ostringstream text;
  text.precision(6);
  text << value;
  return text.str();
}

}  // namespace

TickUnwrapper::TickUnwrapper(int counter_bits, std::string key, std::string wheel)
    : counter_bits_(counter_bits), key_(std::move(key)), wheel_(std::move(wheel))
{
  if (counter_bits < 0 || counter_bits > 52)
    throw std::invalid_argument(key_ + " " + std::to_string(counter_bits) + " is not in [0, 52]");
  period_ = counter_bits > 0 ? std::ldexp(1.0, counter_bits) : 0.0;
}

void TickUnwrapper::restart()
{
  has_previous_ = false;
  has_step_ = false;
}

void TickUnwrapper::checkAliasing(double step, double spacing_s)
{
  if (period_ <= 0.0 || !has_step_)
    return;
  if (std::abs(step - previous_step_) <= 0.5 * period_)
    return;
  refused_ = "wheel " + wheel_ + ": the counter of " + key_ + " " + std::to_string(counter_bits_) +
             " (" + number(period_) + " ticks) aliases: the previous message's step was " +
             number(previous_step_) + " ticks, this one (" + number(spacing_s) +
             " s later) reads " + number(step) + " (more than half a counter turn, " +
             number(0.5 * period_) + ", apart); set " + key_ +
             " to the counter's real width or publish the ticks faster";
  throw std::invalid_argument(refused_);
}

double TickUnwrapper::unwrap(double stamp_s, double raw)
{
  if (!refused_.empty())
    throw std::invalid_argument("refused since an earlier reading: " + refused_);
  if (!std::isfinite(raw) || !std::isfinite(stamp_s))
    throw std::invalid_argument("wheel " + wheel_ + ": a tick reading that is not finite");
  const bool fits =
      period_ > 0.0 ? raw >= -0.5 * period_ && raw < period_ : std::abs(raw) < kExactTicks;
  if (!fits) {
    throw std::invalid_argument(
        "wheel " + wheel_ + ": reading " + number(raw) + " does not fit " + key_ + " " +
        std::to_string(counter_bits_) +
        (period_ > 0.0 ? " (a counter of [" + number(-0.5 * period_) + ", " + number(period_) + "))"
                       : " (no wrap: below 2^53 in magnitude)") +
        "; set " + key_ + " to the counter's width");
  }
  if (!has_previous_) {
    has_previous_ = true;
    previous_raw_ = raw;
    previous_stamp_s_ = stamp_s;
    return cumulative_;
  }
  const double spacing_s = stamp_s - previous_stamp_s_;
  const double step = wrappedDifference(previous_raw_, raw, period_);
  checkAliasing(step, spacing_s);
  previous_step_ = step;
  has_step_ = true;
  cumulative_ += step;
  previous_raw_ = raw;
  previous_stamp_s_ = stamp_s;
  return cumulative_;
}

}  // namespace odometry_calibration
