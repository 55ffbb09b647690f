#include "odometry_calibration/data/encoder_track.h"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <stdexcept>

namespace odometry_calibration {

EncoderTrack::EncoderTrack(std::vector<EncoderChannelOptions> channels, double history_s)
    : decoder_(std::move(channels)), history_s_(history_s)
{
  if (!(history_s_ > 0.0)) {
    throw std::invalid_argument("encoder track history must be > 0 s");
  }
}

EncoderTrack::AddResult EncoderTrack::add(double stamp_s, const Eigen::VectorXd& raw)
{
  AddResult result = AddResult::kAdded;
  if (!samples_.empty() && stamp_s <= lastStamp()) {
    if (stamp_s == lastStamp())
      return AddResult::kDuplicate;
    clear();
    result = AddResult::kRestarted;
  }
  // decode() validates and throws before changing its state.
  samples_.push_back({stamp_s, decoder_.decode(raw)});
  while (samples_.size() > 2 && samples_.front().stamp_s < stamp_s - history_s_) {
    samples_.pop_front();
  }
  return result;
}

void EncoderTrack::clear()
{
  samples_.clear();
  decoder_.reset();
}

std::size_t EncoderTrack::readingsFrom(double stamp_s) const
{
  const auto first =
      std::lower_bound(samples_.begin(), samples_.end(), stamp_s,
                       [](const EncoderSample& sample, double t) { return sample.stamp_s < t; });
  return static_cast<std::size_t>(std::distance(first, samples_.end()));
}

bool EncoderTrack::covers(double stamp_s, double max_gap_s) const
{
  if (samples_.empty() || stamp_s < firstStamp() || stamp_s > lastStamp())
    return false;
  const auto after =
      std::lower_bound(samples_.begin(), samples_.end(), stamp_s,
                       [](const EncoderSample& sample, double t) { return sample.stamp_s < t; });
  if (after->stamp_s == stamp_s)
    return true;
  return after->stamp_s - std::prev(after)->stamp_s <= max_gap_s;
}

EncoderSample EncoderTrack::at(double stamp_s, EncoderInterpolation mode) const
{
  if (samples_.empty() || stamp_s < firstStamp() || stamp_s > lastStamp()) {
    throw std::out_of_range("no encoder data at the requested time");
  }
  return interpolateEncoderSample(samples_, stamp_s, mode);
}

std::vector<EncoderSample> EncoderTrack::between(double start_s, double end_s,
                                                 EncoderInterpolation mode) const
{
  if (samples_.empty() || start_s < firstStamp() || end_s > lastStamp()) {
    throw std::out_of_range("no encoder data over the requested interval");
  }
  if (!(end_s > start_s)) {
    const EncoderSample sample = interpolateEncoderSample(samples_, start_s, mode);
    return {sample, interpolateEncoderSample(samples_, end_s, mode)};
  }
  return cutEncoderWindow(samples_, start_s, end_s, mode);
}

double EncoderTrack::largestGap(double start_s, double end_s) const
{
  // The gaps between samples k - 1 and k with stamp k >= start_s and stamp k - 1 <= end_s: the
  // stamps are in order, so from the first sample at or after start_s (a binary search: the
  // track holds tens of seconds, the pairing asks a few times per scan) up to end_s.
  const auto first =
      std::lower_bound(samples_.begin(), samples_.end(), start_s,
                       [](const EncoderSample& sample, double t) { return sample.stamp_s < t; });
  double largest = 0.0;
  for (auto k = std::max(first, samples_.begin() + std::min<std::ptrdiff_t>(1, samples_.size()));
       k != samples_.end() && std::prev(k)->stamp_s <= end_s; ++k) {
    largest = std::max(largest, k->stamp_s - std::prev(k)->stamp_s);
  }
  return largest;
}

}  // namespace odometry_calibration
