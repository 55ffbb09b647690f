// simulate: runs a scenario and writes a rosbag plus a YAML with the true parameters.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/ros/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/tricycle_log_sink.h"

namespace {

const char* kUsage =
    "usage: simulate SCENARIO.yaml [options]\n"
    "\n"
    "Simulates a robot (diff_drive, tricycle, mecanum; optionally deformed) driving in a 2D\n"
    "world and writes a rosbag with sensor_msgs/JointState, sensor_msgs/LaserScan and the\n"
    "ground truth (nav_msgs/Odometry on /ground_truth/odom, tf tree sim_world -> sim_base_link),\n"
    "plus a YAML file with the true parameters. A fixed seed gives a byte-identical bag.\n"
    "\n"
    "options:\n"
    "  --output BAG      bag to write (default: <scenario name>.bag)\n"
    "  --truth YAML      truth file (default: the bag's name with _truth.yaml)\n"
    "  --seed N          override the scenario's seed\n"
    "  --duration S      override the scenario's duration [s]\n"
    "  --worlds DIR      folder of the shipped worlds (default: the package's config/sim/worlds)\n"
    "  --tricycle-log F  also write the run in the tricycle dataset's text format (tricycle\n"
    "                    robot with the tracker enabled); its header carries the real log's\n"
    "                    nominal values (Ksteer 0.1, Ktraction 0.0106141, axis 1.4, offset 0,\n"
    "                    laser at x = 1.5) as the calibration's starting point\n"
    "  -h, --help        this text\n";

}  // namespace

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  std::string bag_path, truth_path, tricycle_log_path, worlds = sim::shippedWorldsDirectory();
  std::vector<std::string> scenario_paths;
  long long seed = -1;
  sim::ScenarioOverrides overrides;
  try {
    ArgumentParser parser;
    parser.option("--output", &bag_path)
        .option("--truth", &truth_path)
        .option("--tricycle-log", &tricycle_log_path)
        .option("--worlds", &worlds)
        .wholeNumber("--seed", &seed, 0)
        .positiveNumber("--duration", &overrides.duration_s)
        .positionals(&scenario_paths, 1);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (scenario_paths.empty())
      throw ArgumentError("missing the scenario file");
    overrides.seed = static_cast<double>(seed);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const sim::Scenario scenario = sim::loadScenarioYaml(scenario_paths[0], worlds, overrides);
    if (bag_path.empty())
      bag_path = defaultSimulationBagPath(scenario);
    if (truth_path.empty())
      truth_path = defaultTruthPath(bag_path);
    std::unique_ptr<sim::TricycleLogSink> log_sink;
    if (!tricycle_log_path.empty()) {
      if (!sim::canWriteTricycleLog(scenario)) {
        std::cerr << "error: --tricycle-log needs a tricycle robot with 'tracker: {enabled: "
                     "true}' in the scenario\n";
        return 2;
      }
      log_sink = sim::makeTricycleLogSink(scenario);
    }
    const sim::SimulationSummary summary =
        simulateToBag(scenario, bag_path, truth_path, log_sink.get());
    if (log_sink) {
      writeFileAtomically(tricycle_log_path, log_sink->text());
    }
    std::cout << "simulated " << scenario.duration_s << " s of '" << scenario.name << "' ("
              << scenario.robot.type << "): " << summary.joint_states << " joint states, "
              << summary.scans << " scans, " << summary.distance_m << " m driven, "
              << summary.rotation_rad << " rad turned, " << summary.counter_wraps
              << " counter wrap-arounds\n"
              << "bag:   " << bag_path << "\ntruth: " << truth_path << "\n";
    if (sim::droveTooLittle(scenario, summary)) {
      std::cerr << "warning: the robot drove only " << summary.distance_m
                << " m (a script that stands still, or a random planner boxed in near the start "
                   "pose: move start_pose or lower motion.clearance_m); a calibration needs "
                   "motion\n";
    }
    if (log_sink) {
      std::cout << "tricycle log: " << tricycle_log_path << " (" << log_sink->rows() << " rows)\n";
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
