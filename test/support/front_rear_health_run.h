// One simulated drive of the front/rear robot for the health monitor with several sensors
// (issue 35): the simulator's front/rear scenario (config/sim/scenarios/diff_drive_front_rear.yaml,
// a diff drive with a front and a rear 270 deg laser), each laser's scans paired against the
// same encoders by a pair collector of its own (config/diff_drive_front_rear.yaml's sources,
// PLICP as calibrate_bag pairs them), the wheels and both poses fitted jointly on the first
// pairs, one change mid-run (of one laser's mounting or of the wheels) or none, and one monitor
// watching both lasers, every pair tagged with its laser. Used by
// test/assistant/health_monitor_sensors_test.cpp (a few seeds) and
// bench/health_sensors_study.cpp (the seed sweep quoted in docs/multiple_sensors.md).
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/models/joint_fits.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace front_rear_health {

/// The changes of the study.
enum class Change
{
  kNone,         ///< the unchanged twin
  kRearYaw,      ///< the rear laser's mounting yaw +2 deg (issue 35's acceptance)
  kFrontX,       ///< the front laser's mounting x +3 cm
  kRightRadius,  ///< right wheel radius +2 %: every laser sees it
  kSeparation,   ///< wheel separation +3 %
};

inline const char* changeName(Change change)
{
  switch (change) {
    case Change::kNone:
      return "unchanged";
    case Change::kRearYaw:
      return "rear laser yaw +2 deg";
    case Change::kFrontX:
      return "front laser x +3 cm";
    case Change::kRightRadius:
      return "right radius +2 %";
    default:
      return "separation +3 %";
  }
}

/// The laser names the monitor is given (the lasers' frames).
const std::vector<std::string> kLaserNames = {"laser_front", "laser_rear"};

/// The hypothesis (change_hypotheses.h) naming `change` ("" for none).
inline std::string expectedQuantity(Change change)
{
  switch (change) {
    case Change::kRearYaw:
      return "laser_rear mounting yaw";
    case Change::kFrontX:
      return "laser_front mounting x";
    case Change::kRightRadius:
      return "right wheel radius";
    case Change::kSeparation:
      return "wheel separation";
    default:
      return "";
  }
}

/// The laser whose mounting changed (-1: the wheels or nothing).
inline int expectedSensor(Change change)
{
  return change == Change::kRearYaw ? 1 : change == Change::kFrontX ? 0 : -1;
}

struct RunOptions
{
  Change change = Change::kNone;
  unsigned seed = 1;
  double fit_at_s = 124.0;              ///< the joint calibration is fitted on the pairs before [s]
  double change_at_s = 300.0;           ///< [s]
  double within_s = 30.0;               ///< a changed run ends this long after the change [s]
  double unchanged_duration_s = 600.0;  ///< the unchanged twin's drive [s]
};

/// How a verdict reads against the change.
enum class Naming
{
  kRight,       ///< the quantity told, and right
  kSourceOnly,  ///< the right laser (a mounting) or the wheels, the quantity not told
  kCannotTell,  ///< the kind not told, or a mounting of a laser not told
  kWrong,       ///< a wrong kind, a wrong laser or a wrong quantity
  kNothing,     ///< nothing significant
};

inline Naming naming(const ChangeVerdict& verdict, Change change)
{
  if (!verdict.significant)
    return Naming::kNothing;
  if (!verdict.kind_told)
    return Naming::kCannotTell;
  const int sensor = expectedSensor(change);
  if (verdict.kind != (sensor >= 0 ? ChangeKind::kMounting : ChangeKind::kWheel))
    return Naming::kWrong;
  if (verdict.quantity_told)
    return verdict.candidates.front().hypothesis.name == expectedQuantity(change) ? Naming::kRight
                                                                                  : Naming::kWrong;
  if (sensor < 0)
    return Naming::kSourceOnly;  // the wheels, not told which quantity
  return verdict.sensor == sensor ? Naming::kSourceOnly
         : verdict.sensor < 0     ? Naming::kCannotTell
                                  : Naming::kWrong;
}

struct RunResult
{
  bool alarm = false;
  double alarm_delay_s = NAN;  ///< alarm stamp - change time [s]
  std::size_t alarm_sensor = 0;
  std::string message;            ///< the monitor's message at the alarm
  ChangeVerdict at_alarm;         ///< the cause named with the alarm
  ChangeVerdict later;            ///< the cause at the end of the run (within_s after the change)
  double statistic = 0.0;         ///< at the end
  std::size_t pairs[2] = {0, 0};  ///< pairs monitored per laser
};

/// Feeds each laser's scans to its own collector, the encoders to both; keeps the pairs in the
/// order they came, each with its laser.
struct TwoLaserPairs : sim::SimulationSink
{
  struct Tagged
  {
    std::size_t sensor;
    MotionPair pair;
  };
  std::vector<std::unique_ptr<PairCollector>> collectors;
  std::vector<Tagged> pairs;

  explicit TwoLaserPairs(const CalibrationConfig& config)
  {
    for (std::size_t k = 0; k < kLaserNames.size(); ++k) {
      const CalibrationConfig source = configForSource(config, k);
      collectors.push_back(std::make_unique<PairCollector>(
          encoderChannels(source), source.collector, priorPredictor(source)));
    }
  }
  void take(std::size_t k, const std::vector<CollectorEvent>& events)
  {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs.push_back({k, event.pair});
    }
  }
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::Map<const Eigen::VectorXd> raw(s.positions.data(),
                                                static_cast<Eigen::Index>(s.positions.size()));
    for (std::size_t k = 0; k < collectors.size(); ++k)
      take(k, collectors[k]->addEncoders(s.stamp_s, raw));
  }
  void onScan(const sim::ScanSample& s) override
  {
    take(s.laser_index, collectors.at(s.laser_index)->addScan(s.stamp_s, test::toScan(s)));
  }
  void onTruth(const sim::TruthSample&) override {}
  void finish()
  {
    for (std::size_t k = 0; k < collectors.size(); ++k)
      take(k, collectors[k]->flush());
  }
};

inline std::string configDirectory()
{
  return ODOMETRY_CALIBRATION_CONFIG_DIR;
}

/// The scenario of `run` with its change.
inline sim::Scenario scenarioFor(const RunOptions& run)
{
  sim::Scenario scenario =
      sim::loadScenarioYaml(configDirectory() + "/sim/scenarios/diff_drive_front_rear.yaml",
                            sim::shippedWorldsDirectory());
  scenario.seed = run.seed;
  scenario.duration_s =
      run.change == Change::kNone ? run.unchanged_duration_s : run.change_at_s + run.within_s + 1.0;
  sim::ParameterChange c;
  c.at_s = run.change_at_s;
  auto& p = scenario.robot.parameters;
  if (run.change == Change::kRearYaw) {
    c.laser_index = 1;
    c.laser_yaw_change_rad = 2.0 * M_PI / 180.0;
  } else if (run.change == Change::kFrontX) {
    c.laser_x_change_m = 0.03;
  } else if (run.change == Change::kRightRadius) {
    c.robot_parameters["wheel_radius_right_m"] = 1.02 * p.at("wheel_radius_right_m");
  } else if (run.change == Change::kSeparation) {
    c.robot_parameters["wheel_separation_m"] = 1.03 * p.at("wheel_separation_m");
  }
  if (run.change != Change::kNone)
    scenario.changes = {c};
  return scenario;
}

/// Each laser's model after the joint fit: the joint wheels with its own pose (as calibrate_bag
/// writes them).
inline std::vector<WatchedSensor> jointModels(const DiffDriveOptions& nominal,
                                              const JointFitReport& joint)
{
  std::vector<WatchedSensor> sensors;
  for (std::size_t k = 0; k < joint.sensors.size(); ++k) {
    DiffDriveOptions options = nominal;
    options.initial_left_radius_m = joint.intrinsics.at(0).value;
    options.initial_right_radius_m = joint.intrinsics.at(1).value;
    options.initial_separation_m = joint.intrinsics.at(2).value;
    options.initial_T_base_sensor = joint.sensors[k].T_base_sensor;
    sensors.push_back({std::make_shared<DiffDriveModel>(options), kLaserNames.at(k)});
  }
  return sensors;
}

/// The run: simulate, pair, fit jointly, monitor both lasers.
inline RunResult runFrontRear(const RunOptions& run)
{
  const sim::Scenario scenario = scenarioFor(run);
  const CalibrationConfig config =
      loadCalibrationConfig(configDirectory() + "/diff_drive_front_rear.yaml");
  TwoLaserPairs feeder(config);
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, world, *robot, feeder);
  feeder.finish();
  std::vector<std::vector<MotionPair>> calibration(kLaserNames.size());
  std::vector<Pose2> start_poses;
  for (std::size_t k = 0; k < kLaserNames.size(); ++k)
    start_poses.push_back(configForSource(config, k).models.diff_drive.initial_T_base_sensor);
  for (const TwoLaserPairs::Tagged& tagged : feeder.pairs) {
    if (tagged.pair.end_stamp_s <= run.fit_at_s)
      calibration[tagged.sensor].push_back(tagged.pair);
  }
  const DiffDriveOptions nominal = config.models.diff_drive;
  const JointFitReport joint = fitJointDiffDrive(nominal, calibration, start_poses);
  HealthMonitorOptions options;
  options.joint_names = {"left_wheel", "right_wheel"};
  HealthMonitor monitor(jointModels(nominal, joint), options);
  RunResult result;
  for (const TwoLaserPairs::Tagged& tagged : feeder.pairs) {
    if (tagged.pair.start_stamp_s < run.fit_at_s)
      continue;
    ++result.pairs[tagged.sensor];
    if (monitor.addPair(tagged.pair, tagged.sensor)) {
      const HealthStatus status = monitor.status();
      result.alarm = true;
      result.alarm_delay_s = status.alarm_stamp_s - run.change_at_s;
      result.alarm_sensor = status.alarm_sensor;
      result.message = status.message;
      result.at_alarm = status.cause;
    }
  }
  const HealthStatus end = monitor.status();
  result.later = end.cause;
  result.statistic = end.statistic;
  return result;
}

}  // namespace front_rear_health
}  // namespace odometry_calibration
