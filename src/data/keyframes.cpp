#include "odometry_calibration/data/keyframes.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {
constexpr double kStampSlackS = 1e-9;
}  // namespace

std::vector<KeyframeWindow> selectKeyframeWindows(const std::vector<double>& stamps_s,
                                                  double interval_s)
{
  if (!(interval_s > 0.0) || !std::isfinite(interval_s)) {
    throw std::invalid_argument("keyframe interval must be a positive number of seconds");
  }
  std::vector<KeyframeWindow> windows;
  if (stamps_s.empty()) {
    return windows;
  }
  std::size_t keyframe = 0;
  for (std::size_t i = 1; i < stamps_s.size(); ++i) {
    if (!(stamps_s[i] >= stamps_s[i - 1])) {
      std::ostringstream message;
      message << "sample times must not decrease: sample " << i << " at " << stamps_s[i]
              << " s comes after " << stamps_s[i - 1] << " s";
      throw std::invalid_argument(message.str());
    }
    // A nanosecond of slack so that stamps on a regular grid (k * 0.1 s) are not pushed to the
    // next sample by rounding.
    if (stamps_s[i] - stamps_s[keyframe] >= interval_s - kStampSlackS) {
      windows.push_back({keyframe, i});
      keyframe = i;
    }
  }
  return windows;
}

}  // namespace odometry_calibration
