#include "odometry_calibration/session/wheel_topic_watch.h"

#include <cstdio>
#include <utility>

namespace odometry_calibration {

WheelTopicWatch::WheelTopicWatch(std::vector<std::string> topics, double silent_timeout_s,
                                 double start_s)
    : silent_timeout_s_(silent_timeout_s)
{
  for (std::string& name : topics)
    topics_.push_back({std::move(name), start_s, false});
}

void WheelTopicWatch::received(std::size_t wheel, double now_s)
{
  if (wheel >= topics_.size())
    return;
  topics_[wheel].last_message_s = now_s;
  topics_[wheel].silence_said = false;
}

std::vector<std::string> WheelTopicWatch::silentWarnings(double now_s)
{
  const auto silent = [&](const Topic& topic) {
    return now_s - topic.last_message_s > silent_timeout_s_;
  };
  std::vector<std::string> warnings;
  for (std::size_t k = 0; k < topics_.size(); ++k) {
    Topic& topic = topics_[k];
    if (!silent(topic) || topic.silence_said)
      continue;
    const Topic* publishing = nullptr;
    for (const Topic& other : topics_) {
      if (!silent(other)) {
        publishing = &other;
        break;
      }
    }
    if (publishing == nullptr)
      continue;  // all silent: the input monitor's
    topic.silence_said = true;
    char text[600];
    std::snprintf(text, sizeof(text),
                  "wheel topic '%s' (wheels.topics[%zu]) has been silent for %.0f s while '%s' "
                  "publishes: no instant has every wheel's sample, so no pair is made; check "
                  "that its driver publishes",
                  topic.name.c_str(), k, now_s - topic.last_message_s, publishing->name.c_str());
    warnings.emplace_back(text);
  }
  return warnings;
}

}  // namespace odometry_calibration
