#include "odometry_calibration/datasets/tricycle_dataset.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace odometry_calibration {
namespace {

std::vector<std::string> splitWhitespace(const std::string& text)
{
  std::istringstream stream(text);
  std::vector<std::string> tokens;
  std::string token;
  while (stream >> token) {
    tokens.push_back(token);
  }
  return tokens;
}

/// Parses a whole token as a finite double, or returns false.
bool parseDouble(const std::string& token, double* value)
{
  if (token.empty()) {
    return false;
  }
  errno = 0;
  char* end = nullptr;
  *value = std::strtod(token.c_str(), &end);
  return errno == 0 && end == token.c_str() + token.size() && std::isfinite(*value);
}

/// Parses "[ a, b, c ]" or "a b c" into numbers; commas and brackets are separators.
bool parseNumberList(std::string text, std::vector<double>* values)
{
  for (char& c : text) {
    if (c == '[' || c == ']' || c == ',') {
      c = ' ';
    }
  }
  values->clear();
  for (const std::string& token : splitWhitespace(text)) {
    double value = 0.0;
    if (!parseDouble(token, &value)) {
      return false;
    }
    values->push_back(value);
  }
  return true;
}

std::vector<std::string> parseNameList(std::string text)
{
  for (char& c : text) {
    if (c == '[' || c == ']' || c == ',') {
      c = ' ';
    }
  }
  return splitWhitespace(text);
}

/// A UNIX time "1668091584.821040869" split into whole seconds and the fraction, so that the
/// difference of two stamps keeps nanosecond digits.
struct SplitStamp
{
  long long whole_s = 0;
  double fraction_s = 0.0;
};

bool parseStamp(const std::string& token, SplitStamp* stamp)
{
  double check = 0.0;
  if (!parseDouble(token, &check) || check < 0.0) {
    return false;
  }
  const std::size_t dot = token.find('.');
  const std::string whole = token.substr(0, dot);
  stamp->whole_s = std::atoll(whole.c_str());
  stamp->fraction_s = dot == std::string::npos ? 0.0 : std::strtod(token.c_str() + dot, nullptr);
  return true;
}

bool parseTicks(const std::string& token, double* ticks)
{
  if (!parseDouble(token, ticks)) {
    return false;
  }
  return *ticks >= 0.0 && *ticks < 4294967296.0 && std::floor(*ticks) == *ticks;
}

void parseHeaderLine(const std::string& body, std::size_t line, const std::string& source,
                     bool* expect_sensor_pose, TricycleDatasetHeader* header)
{
  const std::size_t colon = body.find(':');
  std::string key = colon == std::string::npos ? body : body.substr(0, colon);
  const std::string value = colon == std::string::npos ? "" : body.substr(colon + 1);
  const auto key_tokens = splitWhitespace(key);
  key = key_tokens.empty() ? "" : key_tokens.front();
  auto fail = [&](const std::string& expected) {
    throw DatasetParseError(source, line, "header '" + key + "': expected " + expected);
  };
  if (key == "kinematic_model") {
    const auto names = splitWhitespace(value);
    header->kinematic_model = names.empty() ? "" : names.front();
  } else if (key == "parameters") {
    header->parameter_names = parseNameList(value);
  } else if (key == "parameter_values") {
    if (!parseNumberList(value, &header->parameter_values))
      fail("a list of numbers");
  } else if (key == "joints_max_enc") {
    header->joint_names = parseNameList(value);
  } else if (key == "joints_max_enc_values") {
    if (!parseNumberList(value, &header->joint_max_values))
      fail("a list of numbers");
  } else if (key == "laser") {
    *expect_sensor_pose = true;
  } else if (key == "translation" && *expect_sensor_pose) {
    std::vector<double> xyz;
    if (!parseNumberList(value, &xyz) || xyz.size() != 3)
      fail("[ x, y, z ] in metres");
    header->T_base_sensor = Pose2(xyz[0], xyz[1], header->T_base_sensor.theta());
    header->has_sensor_pose = true;
  } else if (key == "rotation" && *expect_sensor_pose) {
    std::vector<double> q;
    if (!parseNumberList(value, &q) || q.size() != 4)
      fail("a quaternion [ x, y, z, w ]");
    // Yaw of the quaternion (x, y, z, w).
    const double yaw =
        std::atan2(2.0 * (q[3] * q[2] + q[0] * q[1]), 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2]));
    header->T_base_sensor = Pose2(header->T_base_sensor.x(), header->T_base_sensor.y(), yaw);
    header->has_sensor_pose = true;
  }
  // Other comment lines carry no data we use.
}

/// A pose value beyond this (m or rad) is no pose of a robot but a corrupted number: a tracker
/// x of 1e10 averaged into an ATE of 1.8e8 m, one of 1e308 overflowed the fit.
constexpr double kMaxPoseValue = 1e6;

/// Refuses a sample line that is not 13 tokens with the four labels in their places.
void checkRowLayout(const std::vector<std::string>& tokens, const std::string& source,
                    std::size_t line)
{
  static const char* kLabels[] = {"time:", "ticks:", "model_pose:", "tracker_pose:"};
  static const std::size_t kLabelPositions[] = {0, 2, 5, 9};
  const char* kExpected =
      "'time: <t> ticks: <steer> <traction> model_pose: <x> <y> <theta> "
      "tracker_pose: <x> <y> <theta>'";
  if (tokens.size() != 13) {
    throw DatasetParseError(source, line,
                            "expected 13 tokens " + std::string(kExpected) + ", found " +
                                std::to_string(tokens.size()));
  }
  for (std::size_t i = 0; i < 4; ++i) {
    if (tokens[kLabelPositions[i]] != kLabels[i]) {
      throw DatasetParseError(source, line,
                              "expected label '" + std::string(kLabels[i]) + "' at token " +
                                  std::to_string(kLabelPositions[i] + 1) + ", found '" +
                                  tokens[kLabelPositions[i]] + "'");
    }
  }
}

/// One sample line's tokens: its stamp into `stamp`, the ticks and the two poses into the row
/// (its stamp_s is left to the caller, relative to the first row).
TricycleDatasetRow parseRow(const std::vector<std::string>& tokens, const std::string& source,
                            std::size_t line, SplitStamp* stamp)
{
  checkRowLayout(tokens, source, line);
  TricycleDatasetRow row;
  row.line = line;
  if (!parseStamp(tokens[1], stamp)) {
    throw DatasetParseError(
        source, line, "time: expected a non-negative number of seconds, found '" + tokens[1] + "'");
  }
  if (!parseTicks(tokens[3], &row.steering_ticks) || !parseTicks(tokens[4], &row.traction_ticks)) {
    throw DatasetParseError(
        source, line,
        "ticks: expected two integers in [0, 2^32), found '" + tokens[3] + " " + tokens[4] + "'");
  }
  double values[6];
  const std::size_t value_tokens[] = {6, 7, 8, 10, 11, 12};
  for (std::size_t i = 0; i < 6; ++i) {
    if (!parseDouble(tokens[value_tokens[i]], &values[i])) {
      throw DatasetParseError(source, line,
                              std::string(i < 3 ? "model_pose" : "tracker_pose") +
                                  ": expected a finite number, found '" + tokens[value_tokens[i]] +
                                  "'");
    }
  }
  for (std::size_t i = 0; i < 6; ++i) {
    if (std::abs(values[i]) > kMaxPoseValue) {
      static const char* kNames[] = {"x", "y", "theta"};
      throw DatasetParseError(source, line,
                              std::string(i < 3 ? "model_pose" : "tracker_pose") + " " +
                                  kNames[i % 3] + " = " + tokens[value_tokens[i]] +
                                  " is beyond +-1e6 (m or rad): no pose of the robot, a " +
                                  "corrupted value; remove or repair the line");
    }
  }
  row.T_odom_base_model = Pose2(values[0], values[1], values[2]);
  row.T_world_sensor = Pose2(values[3], values[4], values[5]);
  return row;
}

/// Refuses a tracker pose that leaps away from both neighbours while they agree: a corrupted
/// value (a tracker x of 1000 among poses a few centimetres apart raised the calibrated ATE from
/// 0.38 m to 20 m). A leap counts beyond max(1 m, 100 times the median step) when the
/// neighbours are within a tenth of it of each other.
void refuseTrackerSpikes(const TricycleDataset& dataset)
{
  const std::vector<TricycleDatasetRow>& rows = dataset.rows;
  if (rows.size() < 3)
    return;
  auto distance = [&](std::size_t a, std::size_t b) {
    return std::hypot(rows[a].T_world_sensor.x() - rows[b].T_world_sensor.x(),
                      rows[a].T_world_sensor.y() - rows[b].T_world_sensor.y());
  };
  std::vector<double> steps;
  for (std::size_t i = 1; i < rows.size(); ++i)
    steps.push_back(distance(i - 1, i));
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double leap_m = std::max(1.0, 100.0 * steps[steps.size() / 2]);
  for (std::size_t i = 1; i + 1 < rows.size(); ++i) {
    const double before_m = distance(i - 1, i), after_m = distance(i, i + 1);
    if (before_m > leap_m && after_m > leap_m &&
        distance(i - 1, i + 1) < 0.1 * std::min(before_m, after_m)) {
      throw DatasetParseError(
          dataset.source, rows[i].line,
          "tracker_pose leaps " + std::to_string(before_m) +
              " m away from the lines before and after it (which are " +
              std::to_string(distance(i - 1, i + 1)) +
              " m apart): a corrupted value, which would count in the ATE; remove or repair the "
              "line");
    }
  }
}

}  // namespace

TricycleDataset parseTricycleDataset(std::istream& input, const std::string& source)
{
  TricycleDataset dataset;
  dataset.source = source;
  std::string text;
  std::size_t line = 0;
  bool expect_sensor_pose = false;
  SplitStamp first_stamp;
  while (std::getline(input, text)) {
    ++line;
    // getline stops at EOF without a line end only on the last, unterminated line.
    const bool unterminated = input.eof();
    if (!text.empty() && text.back() == '\r') {
      text.pop_back();
    }
    const auto tokens = splitWhitespace(text);
    if (tokens.empty()) {
      continue;
    }
    if (text.find_first_not_of(" \t") != std::string::npos &&
        text[text.find_first_not_of(" \t")] == '#') {
      if (!dataset.rows.empty()) {
        continue;  // a comment among samples
      }
      parseHeaderLine(text.substr(text.find('#') + 1), line, source, &expect_sensor_pose,
                      &dataset.header);
      continue;
    }
    SplitStamp stamp;
    TricycleDatasetRow row = parseRow(tokens, source, line, &stamp);
    if (dataset.rows.empty()) {
      first_stamp = stamp;
      dataset.first_stamp_unix_s = static_cast<double>(stamp.whole_s) + stamp.fraction_s;
    }
    row.stamp_s = static_cast<double>(stamp.whole_s - first_stamp.whole_s) +
                  (stamp.fraction_s - first_stamp.fraction_s);
    if (!dataset.rows.empty() && row.stamp_s < dataset.rows.back().stamp_s) {
      throw DatasetParseError(source, line,
                              "time goes backwards (" + tokens[1] + " s is before line " +
                                  std::to_string(dataset.rows.back().line) + ")");
    }
    dataset.rows.push_back(row);
    dataset.last_line_unterminated = unterminated;
  }
  refuseTrackerSpikes(dataset);
  return dataset;
}

TricycleDataset loadTricycleDataset(const std::string& path)
{
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw std::runtime_error("'" + path + "' is a directory, not a dataset file");
  }
  std::ifstream file(path);
  if (!file) {
    throw std::runtime_error("cannot open dataset file '" + path + "'");
  }
  return parseTricycleDataset(file, path);
}

}  // namespace odometry_calibration
