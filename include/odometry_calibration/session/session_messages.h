// What the calibration session says, in a form any front end can show: log lines through a
// callback (the node makes them ROS_INFO / ROS_WARN / ROS_ERROR, the bag tool collects them),
// and status reports shaped like diagnostic_msgs/DiagnosticStatus (the node converts them one to
// one) without depending on ROS.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace odometry_calibration {

enum class SessionLogLevel
{
  kInfo,
  kWarn,
  kError
};

/// Receives the session's log lines; may be empty (nothing is said).
using SessionLog = std::function<void(SessionLogLevel, const std::string&)>;

/// One status for /diagnostics: a name, a level, a one-line message and key-value pairs.
struct SessionStatusReport
{
  enum class Level
  {
    kOk,
    kWarn,
    kError  ///< the session cannot go on as configured (e.g. two publishers of one input)
  };
  std::string name;  ///< appended to the front end's own name, e.g. "calibration"
  Level level = Level::kOk;
  std::string message;
  std::vector<std::pair<std::string, std::string>> values;

  void add(const std::string& key, const std::string& value) { values.emplace_back(key, value); }
};

}  // namespace odometry_calibration
