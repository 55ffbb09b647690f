// Decoding of raw wheel/joint encoder readings into values a kinematic model can use.
//
// Two kinds of joints occur on wheeled robots:
//  - incremental (wheels): only differences of consecutive readings mean something. The raw
//    counter may wrap around (e.g. an unsigned 32-bit tick counter) and counts down when the
//    wheel turns backwards, so differences are taken modulo the counter's period into the signed
//    range [-period/2, period/2): a drop of the counter is a reversal, not an overflow, unless it
//    is larger than half the period.
//  - absolute (steering): the reading itself is the angle. Encoders report [0, range); readings
//    above range/2 stand for negative angles (reading - range).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace odometry_calibration {

/// Signed difference current - previous of a counter that wraps with `wrap_period` [raw units],
/// mapped to [-wrap_period/2, wrap_period/2). With wrap_period <= 0 the plain difference.
/// Exact for integer tick counts below 2^53.
double wrappedDifference(double previous_raw, double current_raw, double wrap_period);

/// Signed value of an absolute encoder with `full_range` readings per turn: readings above
/// full_range/2 map to reading - full_range (e.g. 8190 of 8192 -> -2). full_range <= 0: unchanged.
double signedAbsoluteReading(double raw, double full_range);

/// How one encoder channel is decoded.
enum class EncoderKind
{
  kIncremental,  ///< wheel: cumulative count from signed, wrap-safe differences
  kAbsolute,     ///< steering: the (signed) reading itself
};

/// Options of one encoder channel, in the encoder's raw units (ticks or radians).
struct EncoderChannelOptions
{
  std::string name;                              ///< joint name, for messages
  EncoderKind kind = EncoderKind::kIncremental;  ///< incremental or absolute
  /// Incremental: period after which the raw counter wraps (2^32 for a uint32 counter,
  /// 2*pi for an angle that wraps); 0 = never wraps.
  double wrap_period = 0.0;
  /// Absolute: readings per full turn; readings above half of it are negative. 0 = use as is.
  double full_range = 0.0;
  /// The largest plausible speed [raw units / s] (a wheel's, or an absolute joint's slew rate);
  /// a larger step between readings is a glitch (encoder_glitch_filter.h). 0 = unchecked.
  double max_rate_per_s = 0.0;
};

/// Validates options; throws std::invalid_argument naming the channel and the bad field.
void validate(const EncoderChannelOptions& options);

/// Turns successive raw readings of several channels into decoded values: for incremental
/// channels the cumulative count since the first reading (wrap-around and reversal handled),
/// for absolute channels the signed reading. Keeps the last raw reading as state.
class EncoderDecoder
{
public:
  explicit EncoderDecoder(std::vector<EncoderChannelOptions> channels);

  /// Decodes one reading of all channels (same order as the options). Throws
  /// std::invalid_argument on a size mismatch or a non-finite reading, naming the channel.
  Eigen::VectorXd decode(const Eigen::VectorXd& raw);

  /// Forgets the previous reading: the next one starts the cumulative counts at zero again.
  void reset();

  const std::vector<EncoderChannelOptions>& channels() const { return channels_; }

private:
  std::vector<EncoderChannelOptions> channels_;
  bool has_previous_ = false;
  Eigen::VectorXd previous_raw_;
  Eigen::VectorXd cumulative_;
};

}  // namespace odometry_calibration
