// Reader for the Mines ParisTech rover log format (shared/data/mines/README.md): one line per
// scan with a microsecond stamp, cumulative left/right wheel ticks and 683 ranges in mm.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// One line of the log.
struct MinesRecord
{
  std::size_t line = 0;          ///< 1-based line number
  double stamp_s = 0.0;          ///< the line's stamp [s] (the log's microseconds / 1e6)
  double left_ticks = 0.0;       ///< cumulative left wheel ticks (rise driving forward)
  double right_ticks = 0.0;      ///< cumulative right wheel ticks
  std::vector<double> ranges_m;  ///< the first 682 ranges [m]; +inf where the log has 0
};

/// The laser's geometry: 682 rays, ray i at -120 deg + i * 240/681 deg, URG-04LX limits.
constexpr int kMinesRayCount = 682;
/// Time between the log's rays: the URG-04LX sweeps its 1024 steps per turn in 0.1 s [s].
constexpr double kMinesTimePerRayS = 0.1 / 1024.0;
constexpr double kMinesRangeMinM = 0.02;
constexpr double kMinesRangeMaxM = 5.6;

/// Parses a log. Throws std::runtime_error naming `source`, the line and what was expected
/// (707 numeric fields per line, increasing stamps).
std::vector<MinesRecord> parseMinesLog(std::istream& input, const std::string& source);

/// Opens and parses a file.
std::vector<MinesRecord> loadMinesLog(const std::string& path);

/// The record's scan in the core's form.
Scan minesScan(const MinesRecord& record);

}  // namespace odometry_calibration
