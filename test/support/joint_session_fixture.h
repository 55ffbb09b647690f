// What the several-source session's tests share (test/session/joint_calibration_session*_test.cpp):
// the simulated front/rear robot's drives recorded once, fed in stamp order (each laser's scans
// to its own source, as the node feeds them), and the fixture with the configuration.
#pragma once

#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/session/joint_calibration_session.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace test {

namespace fs = std::filesystem;

inline const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A simulated drive's encoder readings and both lasers' scans.
struct Recording : sim::SimulationSink
{
  std::vector<sim::JointStateSample> joints;
  std::vector<sim::ScanSample> scans;
  void onJointState(const sim::JointStateSample& s) override { joints.push_back(s); }
  void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
  void onTruth(const sim::TruthSample&) override {}
};

/// `duration_s` of scenario config/sim/scenarios/`name`.yaml with `seed` and `changes`.
inline Recording simulateScenario(const std::string& name, double duration_s, unsigned seed,
                                  const std::vector<sim::ParameterChange>& changes = {})
{
  Recording r;
  sim::Scenario scenario =
      sim::loadScenarioYaml(kConfig + "/sim/scenarios/" + name + ".yaml", kConfig + "/sim/worlds");
  scenario.duration_s = duration_s;
  scenario.seed = seed;
  scenario.changes = changes;
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, world, *robot, r);
  return r;
}

/// `duration_s` of the front/rear robot (config/sim/scenarios/diff_drive_front_rear.yaml: radii
/// 0.076 / 0.078 m, separation 0.32 m, front laser (0.30, 0, 0), rear (-0.30, 0.02, pi + 0.03))
/// with `seed` and `changes`.
inline Recording simulateFrontRear(double duration_s, unsigned seed,
                                   const std::vector<sim::ParameterChange>& changes = {})
{
  return simulateScenario("diff_drive_front_rear", duration_s, seed, changes);
}

/// 40 s of the front/rear robot, seed 36 (no other test's), recorded once for the suite.
inline const Recording& frontRearDrive()
{
  static const Recording recording = simulateFrontRear(40.0, 36);
  return recording;
}

inline std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline const char* const kFrames[2] = {"laser_front", "laser_rear"};

/// The front/rear robot driving 231 s, seed 37 (no other test's), its rear laser turned by
/// +2 deg at 200 s (a knock on the rear scanner); recorded once for the suite.
inline const Recording& rearLaserTurnedDrive()
{
  static const Recording recording = [] {
    sim::ParameterChange turn;
    turn.at_s = 200.0;
    turn.laser_index = 1;
    turn.laser_yaw_change_rad = 2.0 * M_PI / 180.0;
    return simulateFrontRear(231.0, 37, {turn});
  }();
  return recording;
}

/// Feeds `drive`'s samples from `begin_s` to before `end_s` (seconds after its first sample) in
/// stamp order: the encoders to `joints`, laser k's scans (those of `lasers`) to `scans(k)`.
template <typename Joints, typename Scans>
inline void feedSpan(const Recording& drive, double begin_s, double end_s, const Joints& joints,
                     const Scans& scans, const std::vector<std::size_t>& lasers = {0, 1})
{
  const double t0 = std::min(drive.joints.front().stamp_s, drive.scans.front().stamp_s);
  const auto inSpan = [&](double stamp_s) {
    return stamp_s - t0 >= begin_s && stamp_s - t0 < end_s;
  };
  std::size_t j = 0, s = 0;
  while (j < drive.joints.size() || s < drive.scans.size()) {
    const bool joint =
        s == drive.scans.size() ||
        (j < drive.joints.size() && drive.joints[j].stamp_s <= drive.scans[s].stamp_s);
    if (joint) {
      const auto& positions = drive.joints[j].positions;
      if (inSpan(drive.joints[j].stamp_s))
        joints(drive.joints[j].stamp_s,
               Eigen::Map<const Eigen::VectorXd>(positions.data(), positions.size()));
      ++j;
      continue;
    }
    const sim::ScanSample& scan = drive.scans[s++];
    if (inSpan(scan.stamp_s) &&
        std::find(lasers.begin(), lasers.end(), scan.laser_index) != lasers.end())
      scans(scan.laser_index, scan.stamp_s, test::toScan(scan));
  }
}

/// Feeds the 40 s drive in stamp order (feedSpan over all of it).
template <typename Joints, typename Scans>
inline void feed(const Joints& joints, const Scans& scans, std::vector<std::size_t> lasers = {0, 1})
{
  feedSpan(frontRearDrive(), 0.0, std::numeric_limits<double>::infinity(), joints, scans, lasers);
}

class JointSession : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/joint_calibration_session_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    config_text_ = readFile(kConfig + "/diff_drive_front_rear.yaml");
    // Without the time-offset search: the suite stays short (the offset is the node's rostest's).
    config_text_.replace(config_text_.find("estimate_time_offset: true"), 26,
                         "estimate_time_offset: false");
    config_ = parseCalibrationConfig(config_text_, "diff_drive_front_rear.yaml");
    options_.output_directory = directory_ + "/out";
    options_.wall_clock = [] { return 0.0; };
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// Feeds `session` the drive (the lasers listed).
  void feedJoint(JointCalibrationSession& session, std::vector<std::size_t> lasers = {0, 1})
  {
    feedJointSpan(session, frontRearDrive(), 0.0, std::numeric_limits<double>::infinity(), lasers);
  }

  /// Feeds `session` `drive`'s samples from `begin_s` to before `end_s` (feedSpan).
  void feedJointSpan(JointCalibrationSession& session, const Recording& drive, double begin_s,
                     double end_s, const std::vector<std::size_t>& lasers = {0, 1})
  {
    feedSpan(
        drive, begin_s, end_s,
        [&](double t, const Eigen::VectorXd& raw) { session.addJointPositions(t, raw); },
        [&](std::size_t k, double t, const Scan& scan) {
          session.source(k).addScan(t, scan, kFrames[k]);
        },
        lasers);
    session.flush();
  }

  std::string directory_, config_text_;
  CalibrationConfig config_;
  SessionOptions options_;
};

}  // namespace test
}  // namespace odometry_calibration
