// One wheel's raw tick counter, as a per-wheel topic carries it (a std_msgs integer, often an
// 8-bit counter in a 16-bit message), made a cumulative count. The counter wraps after
// P = 2^counter_bits ticks; each step is taken modulo P into [-P/2, P/2) (encoder.h's
// wrappedDifference), which is only right while the wheel turns less than half a counter turn
// between two messages. A faster wheel aliases: a step of +P/2 + e reads as -P/2 + e, a reversal
// that never happened. The unwrapper predicts each step by the previous one (a driver publishes
// at its own rate; the times the messages carry here, receive or record times, bunch and stall
// with the transport, so the prediction does not scale with them) and refuses a reading whose
// wrapped step lies more than P/2 from it, |s_k - s_{k-1}| > P/2: the counter then turned more
// than half its period since the last message, or its step changed by as much, and no choice of
// wrap count can be trusted. (A message lost in transport is a step as large as two: caught when
// it breaks the same limit.) After a refusal the wheel stays refused (every later reading names
// the first cause): a count that skipped a wrap would be a wrong number in every later pair.
#pragma once

#include <cstdint>
#include <string>

namespace odometry_calibration {

/// Unwraps one wheel's counter readings into a cumulative count [ticks].
class TickUnwrapper
{
public:
  /// `counter_bits`: the counter's width (0: it never wraps); `key` names the setting in
  /// messages ("joints[0].counter_bits"), `wheel` the wheel ("left_wheel on /lwheel"). Throws
  /// std::invalid_argument for counter_bits outside [0, 52].
  TickUnwrapper(int counter_bits, std::string key, std::string wheel);

  /// The cumulative count at `stamp_s` [s] of raw reading `raw` [ticks], counted from the first
  /// reading. Throws std::invalid_argument naming the wheel and the key for a value that is not
  /// finite or does not fit the counter ([-P/2, P) for P = 2^counter_bits; |raw| < 2^53 without
  /// a wrap), for a step that aliases (see above), and for every reading after an aliasing.
  /// Readings must come in time order (the caller refuses others).
  double unwrap(double stamp_s, double raw);

  /// Forgets the readings (time went backwards: a looped bag); an aliasing refusal stays.
  void restart();

  /// The counter's period P [ticks]; 0 when it never wraps.
  double period() const { return period_; }

private:
  /// The aliasing check of a wrapped `step`, `spacing_s` after the previous message (for the
  /// message); throws when it aliases.
  void checkAliasing(double step, double spacing_s);

  double period_ = 0.0;
  int counter_bits_ = 0;
  std::string key_, wheel_;
  bool has_previous_ = false;
  double previous_raw_ = 0.0, previous_stamp_s_ = 0.0, cumulative_ = 0.0;
  bool has_step_ = false;
  double previous_step_ = 0.0;  ///< the previous message's step [ticks]
  std::string refused_;         ///< the aliasing that stopped the wheel ("" while it counts)
};

}  // namespace odometry_calibration
