// Keyframe selection: which samples start and end the intervals that become calibration pairs
// (paper Sec. III: keyframes spaced T seconds apart).
#pragma once

#include <cstddef>
#include <vector>

namespace odometry_calibration {

/// Index of a keyframe interval [first, last] into a sample sequence.
struct KeyframeWindow
{
  std::size_t first = 0;
  std::size_t last = 0;
};

/// Picks keyframes from increasing sample times: the first sample, then each first sample at
/// least `interval_s` [s] after the previous keyframe. Returns the windows between consecutive
/// keyframes. Throws std::invalid_argument if interval_s <= 0 or times decrease.
std::vector<KeyframeWindow> selectKeyframeWindows(const std::vector<double>& stamps_s,
                                                  double interval_s);

}  // namespace odometry_calibration
