#include "odometry_calibration/session/input_monitor.h"

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
}

double InputMonitor::silentFor(const Input& input, double now_s) const
{
  return now_s - (input.messages == 0 ? start_s_ : input.last_message_s);
}

std::vector<std::string> InputMonitor::silentWarnings(double now_s)
{
  std::vector<std::string> warnings;
  for (Input& input : inputs_) {
    const double silent_s = silentFor(input, now_s);
    if (!(silent_s > silent_timeout_s_ && now_s - input.last_warning_s > silent_timeout_s_))
      continue;
    input.last_warning_s = now_s;
    char text[400];
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
  for (Input& input : inputs_) {
    const double rate = (input.messages - input.messages_at_last_rate) / period_s;
    input.messages_at_last_rate = input.messages;
    status->add(input.topic + " rate [Hz]", std::to_string(rate));
    if (silentFor(input, now_s) > silent_timeout_s_)
      problems->push_back("no input on " + input.topic);
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
