// simulate: runs a scenario and writes a rosbag plus a YAML with the true parameters.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

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

bool parseNumber(const std::string& text, double* value)
{
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && std::isfinite(*value);
}

}  // namespace

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  std::string scenario_path, bag_path, truth_path, tricycle_log_path;
  std::string worlds = std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/worlds";
  double seed = -1.0, duration = -1.0;
  const std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    } else if (has_value && arg == "--output") {
      bag_path = args[++i];
    } else if (has_value && arg == "--truth") {
      truth_path = args[++i];
    } else if (has_value && arg == "--tricycle-log") {
      tricycle_log_path = args[++i];
    } else if (has_value && arg == "--worlds") {
      worlds = args[++i];
    } else if (has_value && arg == "--seed") {
      if (!parseNumber(args[++i], &seed) || seed < 0 || seed != std::floor(seed)) {
        std::cerr << "error: --seed needs a whole number >= 0\n";
        return 2;
      }
    } else if (has_value && arg == "--duration") {
      if (!parseNumber(args[++i], &duration) || duration <= 0) {
        std::cerr << "error: --duration needs a number of seconds > 0\n";
        return 2;
      }
    } else if (!arg.empty() && arg[0] != '-' && scenario_path.empty()) {
      scenario_path = arg;
    } else {
      std::cerr << "error: unexpected argument '" << arg << "'\n\n" << kUsage;
      return 2;
    }
  }
  if (scenario_path.empty()) {
    std::cerr << "error: missing the scenario file\n\n" << kUsage;
    return 2;
  }
  try {
    sim::Scenario scenario = sim::loadScenarioYaml(scenario_path, worlds);
    if (seed >= 0)
      scenario.seed = static_cast<unsigned>(seed);
    if (duration > 0)
      scenario.duration_s = duration;
    if (bag_path.empty())
      bag_path = scenario.name + ".bag";
    if (truth_path.empty()) {
      const bool ends_in_bag =
          bag_path.size() > 4 && bag_path.compare(bag_path.size() - 4, 4, ".bag") == 0;
      truth_path =
          (ends_in_bag ? bag_path.substr(0, bag_path.size() - 4) : bag_path) + "_truth.yaml";
    }
    std::unique_ptr<sim::TricycleLogSink> log_sink;
    if (!tricycle_log_path.empty()) {
      if (scenario.robot.type != "tricycle" || !scenario.tracker.enabled) {
        std::cerr << "error: --tricycle-log needs a tricycle robot with 'tracker: {enabled: "
                     "true}' in the scenario\n";
        return 2;
      }
      const auto parameters = sim::makeRobot(scenario.robot)->trueParameters();
      const TricycleParameters nominal = TricycleParameters::fromVectors(
          Eigen::Vector4d(0.1, 0.0106141, 1.4, 0.0), Eigen::Vector3d(1.5, 0.0, 0.0));
      log_sink = std::make_unique<sim::TricycleLogSink>(scenario, nominal,
                                                        parameters.at("steering_ticks_per_rev"),
                                                        parameters.at("traction_ticks_per_rev"));
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
    if (summary.distance_m < 0.05 * scenario.motion.max_speed_mps * scenario.duration_s) {
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
