// Stuck and glitching encoders turn the session's status WARN naming the joint (issue 32).
#include "odometry_calibration/session/encoder_watch.h"

#include <gtest/gtest.h>

#include "odometry_calibration/session/calibration_session.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/files.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

std::vector<EncoderChannelOptions> twoWheels()
{
  EncoderChannelOptions left, right;
  left.name = "left_wheel";
  right.name = "right_wheel";
  return {left, right};
}

TEST(EncoderWatch, NamesAWheelThatStopsCountingWhileTheOtherTurns)
{
  EncoderWatch watch(twoWheels(), 250);
  for (int i = 0; i < 300; ++i)  // standing still: both still, nothing stuck
    watch.add(Eigen::Vector2d(5.0, 7.0));
  EXPECT_TRUE(watch.problems({}).empty());
  for (int i = 1; i < 250; ++i)
    watch.add(Eigen::Vector2d(5.0, 7.0 + i));
  EXPECT_TRUE(watch.problems({}).empty());
  watch.add(Eigen::Vector2d(5.0, 300.0));
  const auto problems = watch.problems({});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("joint 'left_wheel' stuck: the same reading 250 times"),
            std::string::npos)
      << problems[0];
  watch.add(Eigen::Vector2d(6.0, 301.0));  // counting again
  EXPECT_TRUE(watch.problems({}).empty());
}

TEST(EncoderWatch, NamesNewGlitchesOnce)
{
  EncoderWatch watch(twoWheels());
  auto problems = watch.problems({{"right_wheel", 801}});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("joint 'right_wheel' glitching: 801 readings"), std::string::npos)
      << problems[0];
  EXPECT_TRUE(watch.problems({{"right_wheel", 801}}).empty());  // none new since
}

/// The simulated office drive's first 20 s with the left wheel's reading stuck at 1e300 from
/// 10 s on: the status is WARN and names the wheel.
TEST(EncoderWatch, AReadingStuckAtAnAbsurdValueTurnsTheStatusWarn)
{
  struct Drive : sim::SimulationSink
  {
    std::vector<sim::JointStateSample> joints;
    std::vector<sim::ScanSample> scans;
    void onJointState(const sim::JointStateSample& s) override { joints.push_back(s); }
    void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
    void onTruth(const sim::TruthSample&) override {}
  } drive;
  sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office.yaml",
                                                 kConfig + "/sim/worlds");
  scenario.duration_s = 20.0;
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, sim::loadWorldYaml(scenario.world_path), *robot, drive);
  const std::string text = test_support::readFile(kConfig + "/diff_drive.yaml");
  SessionOptions options;
  options.load_saved_calibration = options.resume_pairs = options.assistant = false;
  double clock_s = 0.0;
  options.wall_clock = [&] { return clock_s; };
  CalibrationSession session(parseCalibrationConfig(text, "diff_drive.yaml"), text,
                             "diff_drive.yaml", options);
  std::size_t scan = 0;
  for (const sim::JointStateSample& joints : drive.joints) {
    clock_s = joints.stamp_s;
    for (; scan < drive.scans.size() && drive.scans[scan].stamp_s <= joints.stamp_s; ++scan)
      session.addScan(drive.scans[scan].stamp_s, test::toScan(drive.scans[scan]), "laser");
    Eigen::Vector2d raw(joints.positions[0], joints.positions[1]);
    if (joints.stamp_s > 10.0)
      raw(0) = 1e300;
    session.addJointPositions(joints.stamp_s, raw);
    if (joints.stamp_s > 5.0 && joints.stamp_s < 5.01) {  // before: all well
      EXPECT_EQ(session.statusReports(1.0).front().level, SessionStatusReport::Level::kOk)
          << session.statusReports(1.0).front().message;
    }
  }
  const SessionStatusReport status = session.statusReports(1.0).front();
  EXPECT_EQ(status.level, SessionStatusReport::Level::kWarn);
  // Stuck at one value while the right wheel turns, and every reading a glitch: both said.
  EXPECT_NE(status.message.find("encoder of joint 'left_wheel' stuck"), std::string::npos)
      << status.message;
}

}  // namespace
}  // namespace odometry_calibration
