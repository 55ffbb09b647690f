// The per-wheel tick topics' silence (wheels.source ticks), on the caller's wall clock. A wheel
// topic that falls silent while another still publishes leaves no instant where every wheel has
// a sample (wheel_sample_alignment.h), so no encoder sample and no pair comes: the session's
// input monitor sees the encoders silent and names only the first topic. This names each silent
// wheel topic, once per silence (again only after it published), while another wheel's
// publishes; when every wheel topic is silent the input monitor's warning (or the input's end)
// says it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace odometry_calibration {

class WheelTopicWatch
{
public:
  /// `topics`: the wheels' topics (wheels.topics, the joints' order); times in seconds on any
  /// wall clock, `start_s` when watching began.
  WheelTopicWatch(std::vector<std::string> topics, double silent_timeout_s, double start_s);

  /// A message of wheel `wheel` at `now_s` (a wheel beyond the topics is ignored).
  void received(std::size_t wheel, double now_s);
  /// The warnings due now: each wheel topic silent for more than the timeout while another
  /// wheel's topic published within it.
  std::vector<std::string> silentWarnings(double now_s);

private:
  struct Topic
  {
    std::string name;
    double last_message_s = 0.0;  ///< or the start, before the first message
    bool silence_said = false;
  };
  std::vector<Topic> topics_;
  double silent_timeout_s_;
};

}  // namespace odometry_calibration
