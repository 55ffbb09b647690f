// mines_to_bag: converts the Mines rover log (exp1.dat) to a rosbag with sensor_msgs/JointState
// (left_wheel, right_wheel: cumulative ticks) and sensor_msgs/LaserScan (682 rays, frame
// "laser"), both stamped with the line's time.
#include <iostream>
#include <string>
#include <vector>

#include "odometry_calibration/bag_writers/mines_bag_writer.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/datasets/mines_log.h"

namespace {

const char* kUsage = "usage: mines_to_bag exp1.dat OUTPUT.bag\n";

}  // namespace

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  std::vector<std::string> paths;
  try {
    if (!ArgumentParser().positionals(&paths, 2).parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (paths.size() != 2)
      throw ArgumentError("give the Mines log and the bag to write");
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const std::vector<MinesRecord> records = loadMinesLog(paths[0]);
    if (records.empty())
      throw std::runtime_error(paths[0] + " holds no line");
    writeMinesBag(records, paths[1]);
    std::cout << "wrote " << records.size() << " JointState and LaserScan messages ("
              << records.back().stamp_s - records.front().stamp_s << " s) to " << paths[1] << "\n";
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
