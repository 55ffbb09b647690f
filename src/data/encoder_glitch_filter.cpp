#include "odometry_calibration/data/encoder_glitch_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odometry_calibration {

EncoderGlitchFilter::EncoderGlitchFilter(std::vector<EncoderChannelOptions> channels)
    : channels_(std::move(channels))
{
  for (const auto& channel : channels_)
    validate(channel);
  offset_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(channels_.size()));
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
    const double step = wrappedDifference(from(k), to(k), period);
    // !(<=): a NaN step (inf - inf) is a glitch too.
    if (!(std::abs(step) <= channels_[i].max_rate_per_s * interval_s)) {
      *channel = i;
      *increment = step;
      return false;
    }
  }
  return true;
}

EncoderGlitchFilter::Result EncoderGlitchFilter::filter(double stamp_s, const Eigen::VectorXd& raw)
{
  Result result;
  if (raw.size() != offset_.size())
    throw std::invalid_argument("encoder reading has " + std::to_string(raw.size()) +
                                " values, expected " + std::to_string(offset_.size()));
  for (Eigen::Index i = 0; i < raw.size(); ++i) {
    if (!std::isfinite(raw(i))) {
      throw std::invalid_argument("encoder channel '" +
                                  channels_[static_cast<std::size_t>(i)].name +
                                  "': reading is not a finite number");
    }
  }
  if (anchor_stamp_s_ && stamp_s < *anchor_stamp_s_)
    reset();
  std::size_t channel = 0;
  double increment = 0.0;
  if (anchor_stamp_s_ &&
      !sane(anchor_raw_, raw, stamp_s - *anchor_stamp_s_, &channel, &increment)) {
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
    } else {
      result.glitch = true;
      result.channel = channel;
      result.increment = increment;
      glitch_stamp_s_ = stamp_s;
      glitch_raw_ = raw;
      return result;
    }
  }
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
}

}  // namespace odometry_calibration
