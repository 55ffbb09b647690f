// Reader of the Mines ParisTech rover log (../shared/data/mines/exp1.dat, see its README) for
// the PLICP tests and benchmarks: 682-ray Hokuyo URG-04LX scans and cumulative wheel ticks.
//
// Header-only test helper (shared by test/ and bench/); not part of the library.
#pragma once

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odometry_calibration/datasets/mines_log.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {
namespace mines {

/// Nominal (uncalibrated) robot of the README.
constexpr double kWheelRadiusM = 0.077;
constexpr double kWheelSeparationM = 0.330;
constexpr double kTicksPerRevolution = 2000.0;
constexpr double kLaserAheadOfAxleM = 0.145;
constexpr int kRayCount = kMinesRayCount;
/// Time between rays [s]: the URG-04LX turns at 10 Hz with 1024 steps per revolution and
/// measures its rays counter-clockwise, in the log's ray order (the sensor's data sheet).
constexpr double kTimePerRayS = kMinesTimePerRayS;

/// One line of the log.
struct Record
{
  double stamp_s = 0.0;
  double left_ticks = 0.0;
  double right_ticks = 0.0;
  Scan scan;
};

/// Path of the log under the shared data folder.
inline std::string logPath(const std::string& shared_data_dir)
{
  return shared_data_dir + "/mines/exp1.dat";
}

/// Reads every line with the library's reader (io/mines_log.h); empty when the file is missing.
inline std::vector<Record> loadLog(const std::string& path)
{
  std::vector<Record> records;
  if (!std::ifstream(path))
    return records;
  for (const MinesRecord& line : loadMinesLog(path)) {
    records.push_back({line.stamp_s, line.left_ticks, line.right_ticks, minesScan(line)});
    records.back().scan.time_increment_s = kTimePerRayS;
  }
  return records;
}

/// Motion of the axle centre between two records from the nominal wheel odometry (constant
/// curvature over the interval), in the frame of the first [m, m, rad].
inline Pose2 wheelOdometry(const Record& from, const Record& to)
{
  const double metres_per_tick = 2.0 * M_PI * kWheelRadiusM / kTicksPerRevolution;
  const double left_m = (to.left_ticks - from.left_ticks) * metres_per_tick;
  const double right_m = (to.right_ticks - from.right_ticks) * metres_per_tick;
  const double distance_m = 0.5 * (left_m + right_m);
  const double turn_rad = (right_m - left_m) / kWheelSeparationM;
  // Chord of the arc: length 2 R sin(turn/2) along the mean heading turn/2.
  const double chord_m = std::abs(turn_rad) > 1e-9
                             ? distance_m * std::sin(0.5 * turn_rad) / (0.5 * turn_rad)
                             : distance_m;
  return Pose2(chord_m * std::cos(0.5 * turn_rad), chord_m * std::sin(0.5 * turn_rad), turn_rad);
}

/// The laser's motion for a given axle-centre motion (laser 0.145 m ahead, aligned).
inline Pose2 laserMotion(const Pose2& axle_motion)
{
  return sensorMotionFromBodyMotion(Pose2(kLaserAheadOfAxleM, 0.0, 0.0), axle_motion);
}

/// The laser's velocity while it sweeps scan k, from the nominal odometry, for motion
/// compensation: the mean over the two odometry intervals before line k, which the counters'
/// lead of about one line (README) puts around scan k; zero for the first two lines.
inline SensorVelocity laserVelocity(const std::vector<Record>& records, std::size_t k)
{
  SensorVelocity velocity;
  if (k < 2 || k >= records.size()) {
    return velocity;
  }
  const Pose2 before = laserMotion(wheelOdometry(records[k - 2], records[k - 1]));
  const Pose2 after = laserMotion(wheelOdometry(records[k - 1], records[k]));
  const double duration_s = records[k].stamp_s - records[k - 2].stamp_s;
  velocity.vx_mps = (before.x() + after.x()) / duration_s;
  velocity.vy_mps = (before.y() + after.y()) / duration_s;
  velocity.omega_radps = (before.theta() + after.theta()) / duration_s;
  return velocity;
}

}  // namespace mines
}  // namespace odometry_calibration
