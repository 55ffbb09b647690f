// A simulated drive for the gyro's health monitor: a laser's pairs (rotation with 2 mrad of
// noise, one every 0.5 s) and a 100 Hz gyro (scale 1.015, bias 0.01 rad/s walking
// 3e-6 rad/s/sqrt(s), three times the shipped gyro scenario's, 5 mrad/s of noise, a clock 20 ms
// late), its scale or bias changed from a chosen instant on.
#pragma once

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration::test {

constexpr double kScale = 1.015, kBias = 0.01, kShift = 0.02;

struct Drive
{
  std::vector<std::pair<double, double>> readings;  ///< (gyro stamp, yaw rate reading)
  std::vector<MotionPair> pairs;
};

struct GyroChange
{
  double at_s = 1e9;             ///< from this instant on
  double scale_factor = 1.0;     ///< the scale is multiplied by this
  double bias_step_rad_s = 0.0;  ///< the bias grows by this
};

/// Turns left, straight, right at random lengths, the yaw rate following its target with 0.3 s
/// of lag; truth integrated at 1 kHz.
inline Drive simulateGyroDrive(double duration_s, unsigned seed, const GyroChange& change)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> length(1.5, 4.0);
  const double step = 0.001;
  Drive drive;
  double rate = 0.0, heading = 0.0, bias_walk = 0.0, target = 0.0, segment_end = 0.0;
  double pair_start_heading = 0.0, pair_start = 0.0;
  int segment = 0;
  for (int i = 0; i * step < duration_s; ++i) {
    const double t = i * step;
    if (t >= segment_end) {
      const double targets[4] = {0.6, 0.0, -0.6, 0.0};
      target = targets[segment++ % 4];
      segment_end = t + length(rng);
    }
    if (i % 10 == 0) {  // the 100 Hz gyro, stamped on its own clock
      const bool changed = t >= change.at_s;
      const double scale = kScale * (changed ? change.scale_factor : 1.0);
      const double bias = kBias + bias_walk + (changed ? change.bias_step_rad_s : 0.0);
      drive.readings.emplace_back(t + kShift, scale * rate + bias + 0.005 * normal(rng));
      bias_walk += 3e-6 * std::sqrt(0.01) * normal(rng);
    }
    if (i % 500 == 0 && i > 0) {  // a keyframe pair every 0.5 s
      MotionPair pair;
      pair.start_stamp_s = pair_start;
      pair.end_stamp_s = t;
      pair.sensor_motion = Pose2(0.1, 0.0, heading - pair_start_heading + 0.002 * normal(rng));
      drive.pairs.push_back(pair);
      pair_start = t;
      pair_start_heading = heading;
    }
    rate += (target - rate) * step / 0.3;
    heading += rate * step;
  }
  return drive;
}

}  // namespace odometry_calibration::test
