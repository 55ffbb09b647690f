// A simulated 60 s office drive's messages (test/session): recorded once per test program,
// fed in stamp order as the node and calibrate_bag feed a session.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"

namespace odometry_calibration::test {

/// A simulated drive's messages in stamp order.
struct Recording : sim::SimulationSink
{
  struct Message
  {
    double stamp_s;
    bool joints;
    std::size_t index;
  };
  std::vector<sim::JointStateSample> joints;
  std::vector<sim::ScanSample> scans;
  std::vector<std::string> joint_names;
  void onJointState(const sim::JointStateSample& s) override { joints.push_back(s); }
  void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
  void onTruth(const sim::TruthSample&) override {}

  std::vector<Message> inOrder() const
  {
    std::vector<Message> messages;
    for (std::size_t i = 0; i < joints.size(); ++i)
      messages.push_back({joints[i].stamp_s, true, i});
    for (std::size_t i = 0; i < scans.size(); ++i)
      messages.push_back({scans[i].stamp_s, false, i});
    std::stable_sort(messages.begin(), messages.end(),
                     [](const Message& a, const Message& b) { return a.stamp_s < b.stamp_s; });
    return messages;
  }
};

/// The 120 s simulated office drive (truth: r_L 0.0765, r_R 0.0775, b 0.32 m, laser (0.145,
/// 0.01, 0.02)), recorded once for the suite.
inline const Recording& officeDrive()
{
  static const Recording recording = [] {
    Recording r;
    sim::Scenario scenario = sim::loadScenarioYaml(
        std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/scenarios/diff_drive_office.yaml",
        std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds");
    scenario.duration_s = 60.0;
    const sim::World world = sim::loadWorldYaml(scenario.world_path);
    const auto robot = sim::makeRobot(scenario.robot);
    r.joint_names = sim::publishedJointNames(scenario, *robot);
    sim::simulate(scenario, world, *robot, r);
    return r;
  }();
  return recording;
}

}  // namespace odometry_calibration::test
