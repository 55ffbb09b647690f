// simulate: runs a scenario and writes a rosbag plus a YAML with the true parameters.
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/sim/scenario.h"

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
    "  --output BAG      bag to write (default: <scenario name>.bag; rosbag2: the folder\n"
    "                    <scenario name>)\n"
    "  --format F        bag: a ROS 1 bag (default); db3: a rosbag2 bag folder in SQLite\n"
    "                    storage (CDR messages, metadata.yaml); db3.zstd: the same with its\n"
    "                    storage file compressed with zstd (compression_mode FILE); mcap: a\n"
    "                    rosbag2 bag folder in MCAP storage (CDR messages in chunks, message\n"
    "                    indexes, summary, CRCs)\n"
    "  --chunk-compression C\n"
    "                    the MCAP chunks' compression: zstd (default), lz4 or none\n"
    "  --truth YAML      truth file (default: the bag's name with _truth.yaml)\n"
    "  --seed N          override the scenario's seed\n"
    "  --duration S      override the scenario's duration [s]\n"
    "  --worlds DIR      folder of the shipped worlds (default: the package's config/sim/worlds)\n"
    "  --wheels W        what the wheels publish: joint_state (JointState positions, default),\n"
    "                    ticks (one std_msgs topic per joint, /<joint>_ticks unless the\n"
    "                    scenario's encoders.tick_topics say otherwise) or joint_velocity\n"
    "                    (JointState velocities only, position empty) or odometry (the\n"
    "                    JointState and the base's own nav_msgs/Odometry on /odom)\n"
    "  --odometry-errors T,R\n"
    "                    odometry: the base's translation and rotation scale errors (0.03,0.02:\n"
    "                    it reports 3 % more travel and 2 % more turn than the truth)\n"
    "  --counter-bits N  the counters' width (8: an 8-bit counter wrapping at 256)\n"
    "  --tick-type T     the tick topics' std_msgs type (std_msgs/Int16, Int32, Int64, UInt16,\n"
    "                    UInt32, Float32, Float64; default std_msgs/Int32)\n"
    "  --tick-stagger S  joint j's tick read j * S seconds after each encoder instant\n"
    "  --tricycle-log F  also write the run in the tricycle dataset's text format (tricycle\n"
    "                    robot with the tracker enabled); its header carries the real log's\n"
    "                    nominal values (Ksteer 0.1, Ktraction 0.0106141, axis 1.4, offset 0,\n"
    "                    laser at x = 1.5) as the calibration's starting point\n"
    "  -h, --help        this text\n";

/// "T,R" (--odometry-errors) into the overrides' translation and rotation errors. Throws
/// ArgumentError naming the option for anything else.
void parseOdometryErrors(const std::string& text, odometry_calibration::sim::ScenarioOverrides* o)
{
  std::istringstream in(text);
  char comma = 0;
  if (!(in >> o->odometry_translation_error >> comma >> o->odometry_rotation_error) ||
      comma != ',' || !in.eof()) {
    throw odometry_calibration::ArgumentError("--odometry-errors: '" + text +
                                              "' is not two numbers T,R (e.g. 0.03,0.02)");
  }
}

}  // namespace

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  std::string worlds = sim::shippedWorldsDirectory();
  SimulationFiles files;
  std::vector<std::string> scenario_paths;
  long long seed = -1;
  std::string format = "bag";
  std::string chunk_compression = "zstd";
  sim::ScenarioOverrides overrides;
  long long counter_bits = -1;
  std::string odometry_errors;
  try {
    ArgumentParser parser;
    parser.option("--output", &files.bag_path)
        .option("--truth", &files.truth_path)
        .option("--tricycle-log", &files.tricycle_log_path)
        .option("--worlds", &worlds)
        .option("--format", &format)
        .option("--chunk-compression", &chunk_compression)
        .wholeNumber("--seed", &seed, 0)
        .positiveNumber("--duration", &overrides.duration_s)
        .option("--wheels", &overrides.wheel_output)
        .wholeNumber("--counter-bits", &counter_bits, 0, 52)
        .option("--tick-type", &overrides.tick_type)
        .number("--tick-stagger", &overrides.tick_stagger_s, 0.0)
        .option("--odometry-errors", &odometry_errors)
        .positionals(&scenario_paths, 1);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (scenario_paths.empty())
      throw ArgumentError("missing the scenario file");
    overrides.seed = static_cast<double>(seed);
    overrides.counter_bits = static_cast<int>(counter_bits);
    if (!odometry_errors.empty())
      parseOdometryErrors(odometry_errors, &overrides);
    files.format = bagFormatFromName(format, chunk_compression);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    return simulateToFiles(sim::loadScenarioYaml(scenario_paths[0], worlds, overrides), files,
                           std::cout, std::cerr);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
