#include "odometry_calibration/session/input_monitor.h"

#include <algorithm>
#include <cstdio>

namespace odometry_calibration {
namespace {

/// Repeated warnings about one problem: at most one per this many seconds.
constexpr double kRepeatedWarningS = 5.0;

}  // namespace

InputMonitor::InputMonitor(const std::array<std::string, 2>& topics, double silent_timeout_s,
                           double start_s)
    : silent_timeout_s_(silent_timeout_s), start_s_(start_s)
{
  for (std::size_t i = 0; i < topics.size(); ++i)
    inputs_[i].topic = topics[i];
}

void InputMonitor::received(SessionInput input, double now_s)
{
  Input& entry = inputs_[index(input)];
  ++entry.messages;
  entry.last_message_s = now_s;
  entry.silence_said = false;
}

double InputMonitor::silentFor(const Input& input, double now_s) const
{
  return now_s - (input.messages == 0 ? start_s_ : input.last_message_s);
}

bool InputMonitor::inputEnded(double now_s) const
{
  for (const Input& input : inputs_) {
    if (input.messages == 0 || !(silentFor(input, now_s) > silent_timeout_s_))
      return false;
  }
  return true;
}

std::vector<std::string> InputMonitor::silentWarnings(double now_s)
{
  std::vector<std::string> warnings;
  char text[400];
  if (inputEnded(now_s)) {
    // Every input flowed and all fell silent: the end of a replay (or of the drive). Said once
    // (unless an input's silence was said already), then quiet until an input returns.
    bool said = true;
    for (Input& input : inputs_) {
      said = said && input.silence_said;
      input.silence_said = true;
    }
    if (!said) {
      std::snprintf(text, sizeof(text),
                    "'%s' and '%s' have been silent for %.0f s: the input has ended (the end of "
                    "a replay, or the drivers stopped); quiet until it returns",
                    inputs_[0].topic.c_str(), inputs_[1].topic.c_str(),
                    std::min(silentFor(inputs_[0], now_s), silentFor(inputs_[1], now_s)));
      warnings.push_back(text);
    }
    return warnings;
  }
  for (Input& input : inputs_) {
    const double silent_s = silentFor(input, now_s);
    if (!(silent_s > silent_timeout_s_) || input.silence_said)
      continue;
    input.silence_said = true;  // once per silence: again only after a message
    if (input.messages == 0) {
      std::snprintf(text, sizeof(text),
                    "no message on '%s' after %.0f s: is the topic name right? (rostopic info %s)",
                    input.topic.c_str(), silent_s, input.topic.c_str());
    } else {
      std::snprintf(text, sizeof(text), "'%s' has been silent for %.0f s", input.topic.c_str(),
                    silent_s);
    }
    warnings.push_back(text);
  }
  return warnings;
}

void InputMonitor::addRates(SessionStatusReport* status, std::vector<std::string>* problems,
                            double now_s, double period_s)
{
  const bool ended = inputEnded(now_s);
  for (Input& input : inputs_) {
    // A period of no time (a stopped simulated clock) keeps the count for the next one.
    const double rate =
        period_s > 0.0 ? (input.messages - input.messages_at_last_rate) / period_s : 0.0;
    if (period_s > 0.0)
      input.messages_at_last_rate = input.messages;
    status->add(input.topic + " rate [Hz]", std::to_string(rate));
    if (!ended && silentFor(input, now_s) > silent_timeout_s_)
      problems->push_back("no input on " + input.topic);
  }
  if (ended) {
    char text[120];
    std::snprintf(text, sizeof(text), "ended (all silent for %.0f s)",
                  std::min(silentFor(inputs_[0], now_s), silentFor(inputs_[1], now_s)));
    status->add("input", text);
  }
}

bool InputMonitor::mayWarn(const std::string& problem, double now_s)
{
  const auto found = warnings_.find(problem);
  if (found != warnings_.end() && now_s - found->second < kRepeatedWarningS)
    return false;
  warnings_[problem] = now_s;
  return true;
}

}  // namespace odometry_calibration
