// The health of a session's two inputs (encoders, ego-motion): messages per second (over the
// caller's period), silence beyond a timeout on the wall clock (a warning naming the topic, once
// per silence; all inputs silent after having flowed is the input's end, said once), skipped
// messages, and a limit on repeated bad-input warnings (each distinct problem at once, then at
// most every 5 s).
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "odometry_calibration/session/session_messages.h"

namespace odometry_calibration {

enum class SessionInput
{
  kEncoders = 0,
  kEgoMotion = 1
};

class InputMonitor
{
public:
  /// `topics`: the encoder and ego-motion topics' names, for messages; times in seconds on any
  /// wall clock (the caller's), `start_s` the session's start.
  InputMonitor(const std::array<std::string, 2>& topics, double silent_timeout_s, double start_s);

  void received(SessionInput input, double now_s);
  std::size_t messages(SessionInput input) const { return inputs_[index(input)].messages; }
  /// The warnings due now for silent inputs: each silence said once, again only after the input
  /// returned; all inputs silent after having flowed (the end of a replay) said once as one.
  std::vector<std::string> silentWarnings(double now_s);
  /// Adds "<topic> rate [Hz]" per input (messages since the last call over `period_s`, the
  /// caller's time: ROS time for the node, so a faster replay shows the recorded rates; 0 and
  /// the count kept when no time passed) and a problem per silent input, none when the input
  /// has ended (all silent after having flowed: "input" says so instead).
  void addRates(SessionStatusReport* status, std::vector<std::string>* problems, double now_s,
                double period_s);
  /// Whether a warning about `problem` may be said now (each distinct problem at once, then
  /// at most every 5 s).
  bool mayWarn(const std::string& problem, double now_s);
  const std::string& topic(SessionInput input) const { return inputs_[index(input)].topic; }
  /// Every input had messages and all are silent beyond the timeout (the input has ended).
  bool inputEnded(double now_s) const;

private:
  struct Input
  {
    std::string topic;
    std::size_t messages = 0;
    std::size_t messages_at_last_rate = 0;
    double last_message_s = 0.0;
    bool silence_said = false;  ///< this silence was warned about
  };
  static std::size_t index(SessionInput input) { return static_cast<std::size_t>(input); }
  double silentFor(const Input& input, double now_s) const;

  std::array<Input, 2> inputs_;
  double silent_timeout_s_;
  double start_s_;
  std::map<std::string, double> warnings_;  ///< problem -> when last said [s]
};

}  // namespace odometry_calibration
