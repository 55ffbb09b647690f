#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/session/joint_calibration_session.h"
#include "odometry_calibration/session/wheel_topic_watch.h"

namespace odometry_calibration {
namespace {

TEST(WheelTopicWatch, NamesTheSilentWheelTopicOncePerSilence)
{
  WheelTopicWatch watch({"/lwheel", "/rwheel"}, 5.0, 0.0);
  for (double t = 0.0; t < 10.0; t += 0.03) {
    watch.received(0, t);
    watch.received(1, t + 0.007);
  }
  EXPECT_TRUE(watch.silentWarnings(10.0).empty());
  // The right wheel's driver stops; the left goes on.
  for (double t = 10.0; t < 16.0; t += 0.03)
    watch.received(0, t);
  EXPECT_TRUE(watch.silentWarnings(14.0).empty());  // 4 s: within the timeout
  const std::vector<std::string> warnings = watch.silentWarnings(16.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("wheel topic '/rwheel' (wheels.topics[1]) has been silent for 6 s "
                             "while '/lwheel' publishes"),
            std::string::npos)
      << warnings[0];
  EXPECT_TRUE(watch.silentWarnings(17.0).empty());  // said once
  watch.received(1, 17.5);                          // back, then silent again: said again
  watch.received(0, 23.0);
  EXPECT_EQ(watch.silentWarnings(23.0).size(), 1u);
}

TEST(WheelTopicWatch, AllSilentOrNeverPublishing)
{
  WheelTopicWatch watch({"/lwheel", "/rwheel"}, 5.0, 100.0);
  EXPECT_TRUE(watch.silentWarnings(110.0).empty());  // nothing yet: the input monitor's
  watch.received(0, 111.0);
  // The right wheel never published since the start, 11.5 s ago, while the left does.
  const std::vector<std::string> warnings = watch.silentWarnings(111.5);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'/rwheel' (wheels.topics[1]) has been silent for 12 s"),
            std::string::npos)
      << warnings[0];
  EXPECT_TRUE(watch.silentWarnings(130.0).empty());  // both silent now: the input monitor's
  watch.received(7, 131.0);                          // a wheel beyond the topics: ignored
}

TEST(WheelTopicWatch, TheJointSessionSaysItOnItsTick)
{
  const std::string text =
      "joints: [{name: left_wheel, units_per_turn: 256, counter_bits: 8},\n"
      "         {name: right_wheel, units_per_turn: 256, counter_bits: 8}]\n"
      "wheels: {source: ticks, topics: [/lwheel, /rwheel], message_type: std_msgs/Int16}\n";
  SessionOptions options;
  options.load_saved_calibration = options.resume_pairs = options.assistant = false;
  double clock_s = 0.0;
  options.wall_clock = [&] { return clock_s; };
  std::vector<std::string> said;
  options.log = [&](SessionLogLevel level, const std::string& line) {
    if (level == SessionLogLevel::kWarn)
      said.push_back(line);
  };
  JointCalibrationSession session(parseCalibrationConfig(text, "ticks.yaml"), text, "ticks.yaml",
                                  options);
  int k = 0;
  for (; clock_s < 3.0; clock_s += 0.03, ++k) {
    session.addWheelTick(0, clock_s, k % 256);
    session.addWheelTick(1, clock_s + 0.007, k % 256);
  }
  session.tick();
  EXPECT_TRUE(said.empty()) << said.front();
  for (; clock_s < 9.0; clock_s += 0.03, ++k)  // the right wheel's topic falls silent
    session.addWheelTick(0, clock_s, k % 256);
  session.tick();
  ASSERT_FALSE(said.empty());
  EXPECT_NE(said.back().find("wheel topic '/rwheel' (wheels.topics[1]) has been silent for 6 s "
                             "while '/lwheel' publishes"),
            std::string::npos)
      << said.back();
}

}  // namespace
}  // namespace odometry_calibration
