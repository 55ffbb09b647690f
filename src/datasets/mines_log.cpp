#include "odometry_calibration/datasets/mines_log.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

constexpr std::size_t kFields = 707;
constexpr std::size_t kFirstRange = 24;

}  // namespace

std::vector<MinesRecord> parseMinesLog(std::istream& input, const std::string& source)
{
  std::vector<MinesRecord> records;
  std::string text;
  std::size_t line = 0;
  while (std::getline(input, text)) {
    ++line;
    std::istringstream stream(text);
    std::vector<double> values;
    std::string token;
    while (stream >> token) {
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (*end != '\0' || !std::isfinite(value)) {
        throw std::runtime_error(source + ":" + std::to_string(line) + ": field " +
                                 std::to_string(values.size() + 1) + " is not a number: '" + token +
                                 "'");
      }
      values.push_back(value);
    }
    if (values.empty())
      continue;
    if (values.size() != kFields) {
      throw std::runtime_error(
          source + ":" + std::to_string(line) + ": expected " + std::to_string(kFields) +
          " fields (stamp, counter, left ticks, "
          "right ticks, 20 telemetry fields, 683 ranges), found " +
          std::to_string(values.size()) + (records.empty() ? "" : " (a truncated file?)"));
    }
    MinesRecord record;
    record.line = line;
    record.stamp_s = values[0] * 1e-6;
    record.left_ticks = values[2];
    record.right_ticks = values[3];
    for (int i = 0; i < kMinesRayCount; ++i) {
      const double mm = values[kFirstRange + static_cast<std::size_t>(i)];
      record.ranges_m.push_back(mm > 0.0 ? mm * 1e-3 : std::numeric_limits<double>::infinity());
    }
    if (!records.empty() && record.stamp_s <= records.back().stamp_s) {
      throw std::runtime_error(source + ":" + std::to_string(line) +
                               ": the stamp does not increase");
    }
    records.push_back(std::move(record));
  }
  return records;
}

std::vector<MinesRecord> loadMinesLog(const std::string& path)
{
  std::ifstream file(path);
  if (!file)
    throw std::runtime_error("cannot open log '" + path + "'");
  return parseMinesLog(file, path);
}

Scan minesScan(const MinesRecord& record)
{
  Scan scan;
  scan.angle_min_rad = -120.0 * M_PI / 180.0;
  scan.angle_increment_rad = 240.0 / (kMinesRayCount - 1) * M_PI / 180.0;
  scan.range_min_m = kMinesRangeMinM;
  scan.range_max_m = kMinesRangeMaxM;
  scan.ranges_m = record.ranges_m;
  return scan;
}

}  // namespace odometry_calibration
