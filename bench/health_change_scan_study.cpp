// The health monitor against mid-run changes with scans (issue 34): the seed sweep of
// health_change_study.cpp, but the pairs made as calibrate_bag makes them (PLICP on the
// simulated laser's scans, config/diff_drive.yaml) instead of the pair generator's truth plus
// Gaussian noise. A study printing a table, not a timing benchmark. The office scenario
// (config/sim/scenarios/diff_drive_office.yaml: 682 rays, 240 deg, 10 Hz, 1 cm range noise),
// diff_drive fitted on the pairs of the first 124 s, one change at 300 s (right wheel radius
// +2 %, wheel separation +3 %, laser yaw +1.5 deg, laser x +3 cm) or none, the monitor on every
// pair after the fit; a changed run ends 30 s after the change, an unchanged twin at 600 s.
// Usage: study_health_changes_scans [--seeds 301,302,303,304,305] [--within S] (default 30 s)
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "health_study_table.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/health_change_run.h"
#include "support/sim_recording.h"

namespace {

using namespace odometry_calibration;
using namespace odometry_calibration::health_runs;
using namespace odometry_calibration::health_study;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// Feeds the simulated joint states and scans to a pair collector, in time order.
struct CollectorFeeder : sim::SimulationSink
{
  PairCollector* collector = nullptr;
  std::vector<MotionPair> pairs;
  void take(const std::vector<CollectorEvent>& events)
  {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs.push_back(event.pair);
    }
  }
  void onJointState(const sim::JointStateSample& s) override
  {
    Eigen::VectorXd accepted;
    take(collector->addEncoders(
        s.stamp_s,
        Eigen::Map<const Eigen::VectorXd>(s.positions.data(),
                                          static_cast<Eigen::Index>(s.positions.size())),
        &accepted));
  }
  void onScan(const sim::ScanSample& s) override
  {
    take(collector->addScan(s.stamp_s, test::toScan(s)));
  }
  void onTruth(const sim::TruthSample&) override {}
};

/// The scenario with `change` at change_at_s.
sim::Scenario scenarioFor(Change change, unsigned seed, double change_at_s, double duration_s)
{
  sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office.yaml",
                                                 kConfig + "/sim/worlds");
  scenario.seed = seed;
  scenario.duration_s = duration_s;
  sim::ParameterChange c;
  c.at_s = change_at_s;
  auto& p = scenario.robot.parameters;
  if (change == Change::kRightRadius)
    c.robot_parameters["wheel_radius_right_m"] = 1.02 * p.at("wheel_radius_right_m");
  else if (change == Change::kSeparation)
    c.robot_parameters["wheel_separation_m"] = 1.03 * p.at("wheel_separation_m");
  else if (change == Change::kLaserYaw)
    c.laser_yaw_change_rad = 1.5 * M_PI / 180.0;
  else if (change == Change::kLaserX)
    c.laser_x_change_m = 0.03;
  if (change != Change::kNone)
    scenario.changes = {c};
  return scenario;
}

/// One run: simulate, pair, fit, monitor.
RunResult runWithScans(Change change, unsigned seed, double within_s)
{
  const double fit_at_s = 124.0, change_at_s = 300.0;
  const sim::Scenario scenario = scenarioFor(
      change, seed, change_at_s, change == Change::kNone ? 600.0 : change_at_s + within_s + 1.0);
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  PairCollector collector(encoderChannels(config), config.collector, priorPredictor(config));
  CollectorFeeder feeder;
  feeder.collector = &collector;
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, world, *robot, feeder);
  feeder.take(collector.flush());
  std::shared_ptr<MotionModel> model = makeModel("diff_drive", config.models);
  std::vector<MotionPair> calibration;
  for (const MotionPair& pair : feeder.pairs) {
    if (pair.end_stamp_s <= fit_at_s)
      calibration.push_back(pair);
  }
  model->fit(calibration);
  HealthMonitor monitor(model, HealthMonitorOptions());
  RunResult result;
  for (const MotionPair& pair : feeder.pairs) {
    if (pair.start_stamp_s < fit_at_s)
      continue;
    if (monitor.addPair(pair)) {
      const HealthStatus status = monitor.status();
      result.alarm = true;
      result.alarm_delay_s = status.alarm_stamp_s - change_at_s;
      result.message = status.message;
      result.at_alarm = status.cause;
    }
    if (std::isnan(result.heading_ready_s) &&
        monitor.status().charts[kHeadingDriftSignal].calibrated)
      result.heading_ready_s = pair.end_stamp_s - fit_at_s;
  }
  result.later = monitor.status().cause;
  result.later_valid = result.alarm;
  result.statistic = monitor.status().statistic;
  return result;
}

std::string delay(double seconds)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", seconds);
  return text;
}

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> seed_texts = {"301", "302", "303", "304", "305"};
  double within_s = 30.0;
  if (const int status =
          parseSeedSweep(argc, argv, "study_health_changes_scans", &seed_texts, &within_s);
      status >= 0)
    return status;
  std::printf(
      "| change | seed | alarm after change [s] | cause at the alarm | cause %.0f s after "
      "the change | statistic | heading chart ready after the fit [s] |\n"
      "|---|---|---|---|---|---|---|\n",
      within_s);
  for (const Change change : {Change::kRightRadius, Change::kSeparation, Change::kLaserYaw,
                              Change::kLaserX, Change::kNone}) {
    for (const std::string& seed_text : seed_texts) {
      const unsigned seed = static_cast<unsigned>(std::stoul(seed_text));
      const RunResult r = runWithScans(change, seed, within_s);
      std::printf("| %s | %u | %s | %s | %s | %.2f | %.1f |\n", changeName(change), seed,
                  r.alarm ? delay(r.alarm_delay_s).c_str() : "none",
                  r.alarm ? verdictCell(r.at_alarm).c_str() : "",
                  r.alarm ? verdictCell(r.later).c_str() : "", r.statistic, r.heading_ready_s);
      std::fflush(stdout);
    }
  }
  return 0;
}
