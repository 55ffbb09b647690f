#include "odometry_calibration/data/reference_pairs.h"

#include <stdexcept>

#include "odometry_calibration/data/keyframes.h"

namespace odometry_calibration {
std::vector<MotionPair> referencePairs(const std::vector<EncoderSample>& samples,
                                       const std::vector<Pose2>& T_world_sensor, double interval_s,
                                       const Eigen::Matrix3d& covariance)
{
  if (samples.size() != T_world_sensor.size()) {
    throw std::invalid_argument("reference pairs: one reference pose per encoder sample expected");
  }
  std::vector<double> stamps_s;
  stamps_s.reserve(samples.size());
  for (const EncoderSample& sample : samples) {
    stamps_s.push_back(sample.stamp_s);
  }
  const std::vector<KeyframeWindow> windows = selectKeyframeWindows(stamps_s, interval_s);
  std::vector<MotionPair> pairs;
  pairs.reserve(windows.size());
  for (const KeyframeWindow& window : windows) {
    MotionPair pair;
    pair.start_stamp_s = stamps_s[window.first];
    pair.end_stamp_s = stamps_s[window.last];
    pair.encoder_samples.assign(samples.begin() + static_cast<std::ptrdiff_t>(window.first),
                                samples.begin() + static_cast<std::ptrdiff_t>(window.last) + 1);
    pair.sensor_motion = between(T_world_sensor[window.first], T_world_sensor[window.last]);
    pair.covariance = covariance;
    pairs.push_back(std::move(pair));
  }
  return pairs;
}

}  // namespace odometry_calibration
