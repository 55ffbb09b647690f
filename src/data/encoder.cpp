#include "odometry_calibration/data/encoder.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {

double wrappedDifference(double previous_raw, double current_raw, double wrap_period)
{
  double difference = current_raw - previous_raw;
  if (wrap_period <= 0.0) {
    return difference;
  }
  // Bring the difference into [-period/2, period/2): the shortest signed way around the counter.
  difference -= wrap_period * std::floor(difference / wrap_period + 0.5);
  return difference;
}

double signedAbsoluteReading(double raw, double full_range)
{
  if (full_range > 0.0 && raw > 0.5 * full_range) {
    return raw - full_range;
  }
  return raw;
}

void validate(const EncoderChannelOptions& options)
{
  const std::string who = "encoder channel '" + options.name + "'";
  if (!std::isfinite(options.wrap_period) || options.wrap_period < 0.0) {
    throw std::invalid_argument(who + ": wrap_period must be >= 0 (0 = never wraps)");
  }
  if (!std::isfinite(options.full_range) || options.full_range < 0.0) {
    throw std::invalid_argument(who + ": full_range must be >= 0 (0 = reading used as is)");
  }
  if (!std::isfinite(options.max_rate_per_s) || options.max_rate_per_s < 0.0)
    throw std::invalid_argument(who + ": max_rate_per_s must be >= 0 (0 = unchecked)");
}

EncoderDecoder::EncoderDecoder(std::vector<EncoderChannelOptions> channels)
    : channels_(std::move(channels))
{
  for (const auto& channel : channels_) {
    validate(channel);
  }
  previous_raw_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(channels_.size()));
  cumulative_ = previous_raw_;
}

Eigen::VectorXd EncoderDecoder::decode(const Eigen::VectorXd& raw)
{
  const auto n = static_cast<Eigen::Index>(channels_.size());
  if (raw.size() != n) {
    std::ostringstream message;
    message << "encoder reading has " << raw.size() << " values, expected " << n;
    throw std::invalid_argument(message.str());
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(raw(i))) {
      throw std::invalid_argument("encoder channel '" + channels_[i].name +
                                  "': reading is not a finite number");
    }
  }
  Eigen::VectorXd decoded(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const EncoderChannelOptions& channel = channels_[static_cast<size_t>(i)];
    if (channel.kind == EncoderKind::kAbsolute) {
      decoded(i) = signedAbsoluteReading(raw(i), channel.full_range);
    } else {
      if (has_previous_) {
        cumulative_(i) += wrappedDifference(previous_raw_(i), raw(i), channel.wrap_period);
      }
      decoded(i) = cumulative_(i);
    }
  }
  previous_raw_ = raw;
  has_previous_ = true;
  return decoded;
}

void EncoderDecoder::reset()
{
  has_previous_ = false;
  cumulative_.setZero();
}

}  // namespace odometry_calibration
