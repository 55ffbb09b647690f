// A simulated run recorded for matching studies (the along-track study and its test): the laser
// scans and the ground truth, the truth's pose at any time, a simulated scan as the matcher's.
#pragma once

#include <algorithm>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace test {

/// Collects a run's scans and its truth (the joint states are not needed).
struct ScanTruthRecorder : sim::SimulationSink
{
  std::vector<sim::ScanSample> scans;
  std::vector<sim::TruthSample> truth;
  void onJointState(const sim::JointStateSample&) override {}
  void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
  void onTruth(const sim::TruthSample& s) override { truth.push_back(s); }
};

/// The robot's true pose T_world_base at time t [s]: the latest truth sample before t moved on
/// by its velocity (the truth is sampled every few ms; the velocity changes little within that).
inline Pose2 truthAt(const std::vector<sim::TruthSample>& truth, double t)
{
  auto after =
      std::upper_bound(truth.begin(), truth.end(), t,
                       [](double time, const sim::TruthSample& s) { return time < s.stamp_s; });
  if (after == truth.begin())
    return truth.front().T_world_base;
  const sim::TruthSample& before = *(after - 1);
  return before.T_world_base * sim::integrateTwist(before.twist, t - before.stamp_s);
}

/// A simulated scan as the matcher takes it, with its sweep's time increment.
inline Scan toScan(const sim::ScanSample& sample)
{
  Scan scan;
  scan.angle_min_rad = sample.angle_min_rad;
  scan.angle_increment_rad = sample.angle_increment_rad;
  scan.range_min_m = sample.range_min_m;
  scan.range_max_m = sample.range_max_m;
  scan.time_increment_s = sample.time_increment_s;
  scan.ranges_m.assign(sample.ranges.begin(), sample.ranges.end());
  return scan;
}

}  // namespace test
}  // namespace odometry_calibration
