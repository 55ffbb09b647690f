// A short history of decoded encoder samples from a live stream, with interpolation at any
// instant inside it: keyframes fall between encoder messages, so a pair's encoder samples
// start and end with values interpolated at the keyframes' times.
#pragma once

#include <algorithm>
#include <deque>
#include <iterator>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/data/encoder_interpolation.h"
#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// The samples of [start_s, end_s] from time-ordered `samples`: values interpolated (`mode`) at
/// both ends and every sample strictly inside. Empty when the samples do not cover the interval.
template <class Samples>
std::vector<EncoderSample> cutEncoderWindow(
    const Samples& samples, double start_s, double end_s,
    EncoderInterpolation mode = EncoderInterpolation::kCubic)
{
  if (samples.size() < 2 || !(end_s > start_s) || start_s < samples.front().stamp_s ||
      end_s > samples.back().stamp_s) {
    return {};
  }
  std::vector<EncoderSample> window = {interpolateEncoderSample(samples, start_s, mode)};
  auto it =
      std::upper_bound(samples.begin(), samples.end(), start_s,
                       [](double t, const EncoderSample& sample) { return t < sample.stamp_s; });
  for (; it != samples.end() && it->stamp_s < end_s; ++it)
    window.push_back(*it);
  window.push_back(interpolateEncoderSample(samples, end_s, mode));
  return window;
}

/// Decodes raw readings (wrap-around, absolute ranges) and keeps the recent samples.
class EncoderTrack
{
public:
  /// What add() did.
  enum class AddResult
  {
    kAdded,
    kDuplicate,  ///< same stamp as the last sample: ignored
    kRestarted,  ///< time went backwards (a looping bag, a clock reset): history cleared
  };

  /// `history_s` [s]: how much history to keep behind the newest sample.
  EncoderTrack(std::vector<EncoderChannelOptions> channels, double history_s = 30.0);

  /// Adds a raw reading stamped `stamp_s` [s]. Throws std::invalid_argument (naming the
  /// channel) for a wrong number of values or a non-finite value; the track is unchanged then.
  AddResult add(double stamp_s, const Eigen::VectorXd& raw);

  /// Forgets everything (the next reading starts the cumulative counts at zero again).
  void clear();

  bool empty() const { return samples_.empty(); }
  /// The channels' options.
  const std::vector<EncoderChannelOptions>& channels() const { return decoder_.channels(); }
  double firstStamp() const { return samples_.front().stamp_s; }
  double lastStamp() const { return samples_.back().stamp_s; }

  /// How many kept samples are stamped at or after `stamp_s` [s].
  std::size_t readingsFrom(double stamp_s) const;

  /// Whether `stamp_s` lies within the kept samples, with no gap longer than `max_gap_s` [s]
  /// around it.
  bool covers(double stamp_s, double max_gap_s) const;

  /// Decoded values at `stamp_s`, interpolated (`mode`) between the neighbouring samples.
  /// Requires covers(stamp_s, ...) to hold (throws std::out_of_range otherwise).
  EncoderSample at(double stamp_s, EncoderInterpolation mode = EncoderInterpolation::kCubic) const;

  /// The samples of [start_s, end_s]: interpolated values (`mode`) at both ends and every
  /// sample strictly inside. Requires both ends to be covered (throws std::out_of_range
  /// otherwise).
  std::vector<EncoderSample> between(
      double start_s, double end_s, EncoderInterpolation mode = EncoderInterpolation::kCubic) const;

  /// The longest time between consecutive samples within [start_s, end_s] [s].
  double largestGap(double start_s, double end_s) const;

private:
  EncoderDecoder decoder_;
  double history_s_;
  std::deque<EncoderSample> samples_;
};

}  // namespace odometry_calibration
