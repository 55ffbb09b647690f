// The wheels' samples of per-wheel topics, each wheel stamped on its own, made joint samples at
// common instants: the instants are the first wheel's stamps t; every other wheel's value at t
// is interpolated linearly between its samples a <= t <= b,
//   c(t) = c_a + (c_b - c_a) (t - t_a) / (t_b - t_a),
// so an instant is complete once every other wheel has a sample at or after it. An instant before
// another wheel's first sample, or whose samples a, b lie more than max_bracket_s apart (a wheel's
// topic fell silent), is dropped: the joint stream then has a gap there, which the pair collector
// sees (keyframes.max_encoder_gap_s) instead of a guess across it.
#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// Aligns the samples of `wheels` wheels to the first wheel's instants.
class WheelSampleAligner
{
public:
  /// Throws std::invalid_argument for no wheel or a max_bracket_s that is not positive [s].
  WheelSampleAligner(std::size_t wheels, double max_bracket_s);

  /// Wheel `wheel`'s value at `stamp_s` [s]; returns the joint samples this completes, in time
  /// order (values in wheel order). A stamp equal to the wheel's last is ignored. Throws
  /// std::invalid_argument for a wheel beyond the count, a value or stamp that is not finite,
  /// and a stamp before the wheel's last (the alignment then restarts from the next sample).
  std::vector<EncoderSample> add(std::size_t wheel, double stamp_s, double value);

  /// Forgets every sample.
  void restart();

  /// Instants dropped so far (before another wheel's first sample, or across a gap).
  std::size_t droppedInstants() const { return dropped_; }

private:
  struct Sample
  {
    double stamp_s;
    double value;
  };
  /// The complete instants at the front of pending_, emitted into `out`.
  void emitComplete(std::vector<EncoderSample>& out);

  std::size_t wheels_;
  double max_bracket_s_;
  std::deque<Sample> pending_;              ///< the first wheel's instants not yet complete
  std::vector<std::deque<Sample>> others_;  ///< wheel w's recent samples at others_[w]
  std::vector<double> last_stamp_s_;        ///< each wheel's newest stamp (NaN: none)
  std::size_t dropped_ = 0;
};

}  // namespace odometry_calibration
