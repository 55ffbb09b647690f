// Encoder glitches: a reading whose increment is beyond what the wheel can physically turn in
// the time since the previous reading (a bit flip, a bus error, a driver that reports garbage
// once) is not motion. The filter skips such readings and re-anchors on the next sane one, so
// a glitch never enters the cumulative counts that odometry and pairs are made of.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"

namespace odometry_calibration {

/// Looks at successive raw readings of the channels and tells glitches from motion. Channels
/// with a `max_rate_per_s` (> 0) are checked: incremental wheels and absolute joints (a steering
/// angle that leaps by more than the joint can turn is a glitch too; its step wraps at the
/// channel's full_range, if any).
///
/// A reading is sane when every checked channel's increment (wrap-safe) since the last accepted
/// reading is at most max_rate_per_s * max(dt, kMinInterval_s) (stamps jitter, so at least 0.1 s of
/// motion is always allowed), and, for a counter that wraps, its readings are within
/// (-wrap_period, wrap_period). A reading that is not sane is a glitch and is skipped. The next
/// reading is accepted when it is sane against the last accepted reading (a one-message spike)
/// or against the glitch reading itself (the counter jumped and stays there, e.g. a driver
/// restart): then, for an incremental channel, the jump is absorbed into an offset and the
/// counts go on from where they were (the motion during the jump is lost; the pairing drops the
/// interval around it); an absolute channel's new reading is taken as it is.
///
/// Once two readings were accepted in a row, a reading must also be steady: its step from the
/// last accepted reading at most what the joint covers from rest over dt at an acceleration
/// that reaches max_rate_per_s within kMinInterval_s (huge for a wheel), plus a dither of
/// max_rate_per_s * kDither_s, plus, when the joint was moving and the step goes on the same
/// way, kSteadyFactor times the motion at the last step's speed over max(dt, that step's
/// interval). A step that turns back stopped first and gets no speed term. A driver that puts
/// a reading of 0 between its real ones sends steps within the rate limit while the wheel is
/// within a few turns of 0, yet hundreds of times its motion and each back the other way;
/// a reading stamped close after the last one (bunched stamps) keeps the last interval's room.
/// A stream that starts with such readings is steady on its own terms: it is caught once a
/// step leaves the rate limit, and re-anchors on the first reading after that.
class EncoderGlitchFilter
{
public:
  /// Readings less than this far apart [s] may still move by max_rate_per_s * kMinInterval_s.
  static constexpr double kMinInterval_s = 0.1;
  /// A steady step is at most this many times the motion at the last step's speed (plus the
  /// start from rest over dt).
  static constexpr double kSteadyFactor = 4.0;
  /// The dither a steady step may always have: max_rate_per_s times this [s].
  static constexpr double kDither_s = 1e-4;

  /// Validates the channels (throws std::invalid_argument).
  explicit EncoderGlitchFilter(std::vector<EncoderChannelOptions> channels);

  /// What filter() found.
  struct Result
  {
    bool glitch = false;      ///< the reading is skipped
    std::size_t channel = 0;  ///< the first channel beyond its limit (if glitch)
    double increment = 0.0;   ///< that channel's increment [raw units] (if glitch)
    /// The increment is a whole counter turn of 2^bits (16 <= bits <= 52) give or take what the
    /// channel can turn in the interval: a counter wrapping that no counter_bits describes (0:
    /// not that, if glitch).
    int wrap_bits = 0;
    Eigen::VectorXd corrected;  ///< the reading to use, jumps removed (if not a glitch)
    /// The reading ends a run of skipped glitches and is sane against the reading before them:
    /// the counts went on without a jump, nothing was lost in between.
    bool continuous = false;
  };

  /// Checks the reading stamped `stamp_s` [s]. A reading stamped before the last one starts
  /// over (it becomes the anchor). `raw` must hold one finite value per channel.
  Result filter(double stamp_s, const Eigen::VectorXd& raw);

  /// The counter size 2^bits (16 <= bits <= 52) that `increment` [raw units] is a whole turn
  /// of, give or take `motion` [raw units] (what the channel can turn in the interval), or 0.
  static int counterWrapBits(double increment, double motion);

  /// Forgets the anchor (the next reading is accepted as it is, offsets kept).
  void reset();

private:
  /// The reading is a glitch on `channel` (its `increment` over `dt_s` [s]): remembered as the
  /// last reading, skipped.
  Result skip(double stamp_s, const Eigen::VectorXd& raw, std::size_t channel, double increment,
              double dt_s);
  bool sane(const Eigen::VectorXd& from, const Eigen::VectorXd& to, double dt_s,
            std::size_t* channel, double* increment) const;
  /// Whether the step from the anchor to `to` is steady (see the class comment); true while
  /// no step between two accepted readings is known.
  bool steady(const Eigen::VectorXd& to, double dt_s, std::size_t* channel,
              double* increment) const;
  /// The wrap-safe step of channel i from `from` to `to`.
  double step(std::size_t i, double from, double to) const;

  std::vector<EncoderChannelOptions> channels_;
  std::optional<double> anchor_stamp_s_;  ///< last accepted reading
  Eigen::VectorXd anchor_raw_;
  std::optional<double> last_step_dt_s_;  ///< the interval of the last accepted step
  Eigen::VectorXd last_step_;             ///< the last accepted step, per channel
  std::optional<double> glitch_stamp_s_;  ///< last reading, if it was a glitch
  Eigen::VectorXd glitch_raw_;
  Eigen::VectorXd offset_;  ///< subtracted from raw readings: the absorbed jumps
};

}  // namespace odometry_calibration
