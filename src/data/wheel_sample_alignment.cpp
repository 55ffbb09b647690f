#include "odometry_calibration/data/wheel_sample_alignment.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace odometry_calibration {

WheelSampleAligner::WheelSampleAligner(std::size_t wheels, double max_bracket_s)
    : wheels_(wheels), max_bracket_s_(max_bracket_s), others_(wheels)
{
  if (wheels == 0)
    throw std::invalid_argument("wheel sample alignment of no wheel");
  if (!(max_bracket_s > 0.0) || !std::isfinite(max_bracket_s))
    throw std::invalid_argument("wheel sample alignment: the largest bracket must be positive");
  restart();
}

void WheelSampleAligner::restart()
{
  pending_.clear();
  for (auto& samples : others_)
    samples.clear();
  last_stamp_s_.assign(wheels_, std::numeric_limits<double>::quiet_NaN());
}

std::vector<EncoderSample> WheelSampleAligner::add(std::size_t wheel, double stamp_s, double value)
{
  if (wheel >= wheels_) {
    throw std::invalid_argument("wheel " + std::to_string(wheel) + " of " +
                                std::to_string(wheels_) + " wheels");
  }
  if (!std::isfinite(stamp_s) || !std::isfinite(value))
    throw std::invalid_argument("wheel " + std::to_string(wheel) + ": a stamp or value not finite");
  const double last = last_stamp_s_[wheel];
  if (stamp_s == last)
    return {};
  if (stamp_s < last) {
    restart();
    throw std::invalid_argument("wheel " + std::to_string(wheel) + "'s time went back by " +
                                std::to_string(last - stamp_s) +
                                " s (a looped bag, a clock reset): the wheels' alignment restarts");
  }
  last_stamp_s_[wheel] = stamp_s;
  if (wheel == 0)
    pending_.push_back({stamp_s, value});
  else
    others_[wheel].push_back({stamp_s, value});
  std::vector<EncoderSample> out;
  emitComplete(out);
  return out;
}

void WheelSampleAligner::emitComplete(std::vector<EncoderSample>& out)
{
  while (!pending_.empty()) {
    const Sample instant = pending_.front();
    EncoderSample joint{instant.stamp_s, Eigen::VectorXd(static_cast<Eigen::Index>(wheels_))};
    joint.values(0) = instant.value;
    bool drop = false;
    for (std::size_t w = 1; w < wheels_; ++w) {
      std::deque<Sample>& samples = others_[w];
      if (samples.empty() || samples.back().stamp_s < instant.stamp_s)
        return;  // wait for wheel w's sample at or after the instant
      if (samples.front().stamp_s > instant.stamp_s) {
        drop = true;  // before wheel w's first sample: cannot be interpolated
        continue;
      }
      while (samples.size() > 1 && samples[1].stamp_s <= instant.stamp_s)
        samples.pop_front();  // samples[0] is now the last one at or before the instant
      const Sample& a = samples[0];
      const Sample& b = samples.size() > 1 ? samples[1] : samples[0];
      if (b.stamp_s - a.stamp_s > max_bracket_s_) {
        drop = true;
        continue;
      }
      const double fraction =
          b.stamp_s > a.stamp_s ? (instant.stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s) : 0.0;
      joint.values(static_cast<Eigen::Index>(w)) = a.value + fraction * (b.value - a.value);
    }
    pending_.pop_front();
    if (drop)
      ++dropped_;
    else
      out.push_back(std::move(joint));
  }
}

}  // namespace odometry_calibration
