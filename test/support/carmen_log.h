// Reader of the real CARMEN laser logs with SLAM-corrected poses (../shared/data/carmen, see its
// README): FLASER lines, n ranges over 180 deg, first ray at -90 deg, counter-clockwise, ray
// spacing 180/(n-1) deg; readings <= 0 or >= 80 m are no return. Both pose triples of a line hold
// the corrected pose of the robot (laser at its origin). For the side-by-side PLICP benchmark and
// the test guarding the matcher's failures on these logs.
//
// Header-only test and benchmark helper; not part of the library. The files are read through
// `gzip -dcf` (gzip'ed or plain text; no copy of the data is made).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {
namespace carmen {

/// Readings at or beyond this are no return [m] (the README).
constexpr double kNoReturnM = 80.0;

/// One FLASER line: the scan and the corrected pose of the robot in the map frame.
struct Record
{
  Scan scan;
  Pose2 T_map_robot;
};

/// The scan of n readings over 180 deg; no-return readings are marked by the range limits
/// (range_min_m just above 0, range_max_m just below 80 m) and by a NaN.
inline Scan flaserScan(const std::vector<double>& readings_m)
{
  Scan scan;
  const std::size_t n = readings_m.size();
  scan.angle_min_rad = -0.5 * M_PI;
  scan.angle_increment_rad = M_PI / static_cast<double>(n - 1);
  scan.range_min_m = 1e-3;
  scan.range_max_m = kNoReturnM - 1e-3;
  for (const double r : readings_m) {
    scan.ranges_m.push_back(r > 0.0 && r < kNoReturnM ? r
                                                      : std::numeric_limits<double>::quiet_NaN());
  }
  return scan;
}

/// Every FLASER line of a CARMEN log (gzip'ed or plain); empty when the file cannot be read
/// (or its path holds a quote, which the shell command below cannot take).
inline std::vector<Record> loadLog(const std::string& path)
{
  std::vector<Record> records;
  if (path.find('\'') != std::string::npos)
    return records;
  const std::string command = "gzip -dcf '" + path + "' 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe)
    return records;
  std::string text;
  char buffer[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe.get())) > 0)
    text.append(buffer, got);
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string tag;
    int n = 0;
    if (!(fields >> tag) || tag != "FLASER" || !(fields >> n) || n < 2)
      continue;
    std::vector<double> readings(static_cast<std::size_t>(n));
    for (double& r : readings)
      fields >> r;
    double x = 0.0, y = 0.0, theta = 0.0;
    if (!(fields >> x >> y >> theta))
      continue;
    records.push_back({flaserScan(readings), Pose2(x, y, theta)});
  }
  return records;
}

/// Path of a log under the shared data folder (`name`: aces, fhw, freiburg-079, ...).
inline std::string logPath(const std::string& shared_data_dir, const std::string& name)
{
  return shared_data_dir + "/carmen/" + name + "-corrected.log.gz";
}

/// Every CARMEN log (`*.log.gz` or `*.log`) directly in `folder`, sorted by name; empty when the
/// folder is absent.
inline std::vector<std::string> logsIn(const std::string& folder)
{
  std::vector<std::string> paths;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    const auto endsWith = [&name](const std::string& end) {
      return name.size() > end.size() &&
             name.compare(name.size() - end.size(), end.size(), end) == 0;
    };
    if (entry.is_regular_file() && (endsWith(".log.gz") || endsWith(".log")))
      paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

/// A log's short name: its file name up to the first '.' and without "-corrected".
inline std::string logName(const std::string& path)
{
  std::string stem = path.substr(path.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find('.'));
  const std::string suffix = "-corrected";
  if (stem.size() > suffix.size() &&
      stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0)
    stem.resize(stem.size() - suffix.size());
  return stem;
}

}  // namespace carmen
}  // namespace odometry_calibration
