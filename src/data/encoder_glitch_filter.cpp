#include "odometry_calibration/data/encoder_glitch_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odometry_calibration {
namespace {

/// Throws std::invalid_argument for a reading of the wrong size or with a non-finite value.
void checkReading(const std::vector<EncoderChannelOptions>& channels, const Eigen::VectorXd& raw)
{
  if (raw.size() != static_cast<Eigen::Index>(channels.size()))
    throw std::invalid_argument("encoder reading has " + std::to_string(raw.size()) +
                                " values, expected " + std::to_string(channels.size()));
  for (Eigen::Index i = 0; i < raw.size(); ++i) {
    if (!std::isfinite(raw(i))) {
      throw std::invalid_argument("encoder channel '" + channels[static_cast<std::size_t>(i)].name +
                                  "': reading is not a finite number");
    }
  }
}

}  // namespace

EncoderGlitchFilter::EncoderGlitchFilter(std::vector<EncoderChannelOptions> channels)
    : channels_(std::move(channels))
{
  for (const auto& channel : channels_)
    validate(channel);
  offset_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(channels_.size()));
}

double EncoderGlitchFilter::step(std::size_t i, double from, double to) const
{
  // An absolute reading with a full range wraps there (359 deg -> 1 deg is a 2 deg step).
  const double period = channels_[i].kind == EncoderKind::kIncremental ? channels_[i].wrap_period
                                                                       : channels_[i].full_range;
  return wrappedDifference(from, to, period);
}

bool EncoderGlitchFilter::steady(const Eigen::VectorXd& to, double dt_s, std::size_t* channel,
                                 double* increment) const
{
  if (!last_step_dt_s_)
    return true;
  const double dt = std::max(dt_s, 0.0);
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    if (channels_[i].max_rate_per_s <= 0.0)
      continue;
    const auto k = static_cast<Eigen::Index>(i);
    const double change = step(i, anchor_raw_(k), to(k));
    // From rest, or turning back against the last step (the joint stopped first): at most
    // what it covers accelerating to max_rate_per_s within kMinInterval_s (huge for a wheel),
    // plus a dither. Going on the same way: also kSteadyFactor times the motion at its last
    // speed over max(dt, the last step's interval), so that a reading stamped close after
    // the last one (bunched stamps) keeps that interval's room.
    const double rate = channels_[i].max_rate_per_s;
    const double speed = std::abs(last_step_(k)) / *last_step_dt_s_;
    const bool reverses = change * last_step_(k) < 0.0;
    const double from_rest = 0.5 * rate / kMinInterval_s * dt * dt + rate * kDither_s;
    const double allowed = reverses || speed == 0.0
                               ? from_rest
                               : from_rest + kSteadyFactor * speed * std::max(dt, *last_step_dt_s_);
    if (!(std::abs(change) <= allowed)) {
      *channel = i;
      *increment = change;
      return false;
    }
  }
  return true;
}

bool EncoderGlitchFilter::sane(const Eigen::VectorXd& from, const Eigen::VectorXd& to, double dt_s,
                               std::size_t* channel, double* increment) const
{
  const double interval_s = std::max(dt_s, kMinInterval_s);
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    if (channels_[i].max_rate_per_s <= 0.0)
      continue;
    const auto k = static_cast<Eigen::Index>(i);
    // An absolute reading with a full range wraps there (359 deg -> 1 deg is a 2 deg step).
    const double period = channels_[i].kind == EncoderKind::kIncremental ? channels_[i].wrap_period
                                                                         : channels_[i].full_range;
    if (period > 0.0 && (!(std::abs(from(k)) < period) || !(std::abs(to(k)) < period))) {
      // Beyond the counter's range (differences of such numbers lose every digit).
      *channel = i;
      *increment = to(k) - from(k);
      return false;
    }
    const double change = step(i, from(k), to(k));
    // !(<=): a NaN step (inf - inf) is a glitch too.
    if (!(std::abs(change) <= channels_[i].max_rate_per_s * interval_s)) {
      *channel = i;
      *increment = change;
      return false;
    }
  }
  return true;
}

int EncoderGlitchFilter::counterWrapBits(double increment, double motion)
{
  const double size = std::abs(increment);
  if (!std::isfinite(size) || !(size > 0.0))
    return 0;
  const int bits = static_cast<int>(std::lround(std::log2(size)));
  if (bits < 16 || bits > 52)
    return 0;
  return std::abs(size - std::ldexp(1.0, bits)) <= motion ? bits : 0;
}

EncoderGlitchFilter::Result EncoderGlitchFilter::skip(double stamp_s, const Eigen::VectorXd& raw,
                                                      std::size_t channel, double increment,
                                                      double dt_s)
{
  Result result;
  result.glitch = true;
  result.channel = channel;
  result.increment = increment;
  const EncoderChannelOptions& options = channels_[channel];
  if (options.kind == EncoderKind::kIncremental && options.wrap_period <= 0.0) {
    result.wrap_bits =
        counterWrapBits(increment, options.max_rate_per_s * std::max(dt_s, kMinInterval_s));
  }
  glitch_stamp_s_ = stamp_s;
  glitch_raw_ = raw;
  return result;
}

EncoderGlitchFilter::Result EncoderGlitchFilter::filter(double stamp_s, const Eigen::VectorXd& raw)
{
  Result result;
  checkReading(channels_, raw);
  if (anchor_stamp_s_ && stamp_s < *anchor_stamp_s_)
    reset();
  std::size_t channel = 0;
  double increment = 0.0;
  const double dt_s = anchor_stamp_s_ ? stamp_s - *anchor_stamp_s_ : 0.0;
  const bool after_glitch = glitch_stamp_s_.has_value();
  bool jumped = false;
  if (anchor_stamp_s_ && !(sane(anchor_raw_, raw, dt_s, &channel, &increment) &&
                           steady(raw, dt_s, &channel, &increment))) {
    std::size_t ignored_channel = 0;
    double ignored_increment = 0.0;
    if (glitch_stamp_s_ && stamp_s >= *glitch_stamp_s_ &&
        sane(glitch_raw_, raw, stamp_s - *glitch_stamp_s_, &ignored_channel, &ignored_increment)) {
      // The counter jumped and stayed: continue from the jumped value, counting no motion
      // across the jump. An absolute reading that stays is simply where the joint is now.
      for (Eigen::Index i = 0; i < raw.size(); ++i) {
        const auto& options = channels_[static_cast<std::size_t>(i)];
        if (options.kind == EncoderKind::kIncremental)
          offset_(i) += wrappedDifference(anchor_raw_(i), glitch_raw_(i), options.wrap_period);
      }
      jumped = true;
    } else {
      return skip(stamp_s, raw, channel, increment, dt_s);
    }
  }
  // The step just accepted, for the next reading's steadiness (none across a jump or a restart;
  // a repeated stamp says nothing of the rate).
  if (anchor_stamp_s_ && !jumped && dt_s > 0.0) {
    last_step_.resize(raw.size());
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      last_step_(k) = step(i, anchor_raw_(k), raw(k));
    }
    last_step_dt_s_ = dt_s;
  } else if (!anchor_stamp_s_ || jumped) {
    last_step_dt_s_.reset();
  }
  result.continuous = after_glitch && !jumped;
  anchor_stamp_s_ = stamp_s;
  anchor_raw_ = raw;
  glitch_stamp_s_.reset();
  result.corrected = raw - offset_;
  for (Eigen::Index i = 0; i < raw.size(); ++i) {
    if (channels_[static_cast<std::size_t>(i)].kind != EncoderKind::kIncremental)
      result.corrected(i) = raw(i);
  }
  return result;
}

void EncoderGlitchFilter::reset()
{
  anchor_stamp_s_.reset();
  glitch_stamp_s_.reset();
  last_step_dt_s_.reset();
}

}  // namespace odometry_calibration
