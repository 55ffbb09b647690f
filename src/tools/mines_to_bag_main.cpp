// mines_to_bag: converts the Mines rover log (exp1.dat) to a rosbag with sensor_msgs/JointState
// (left_wheel, right_wheel: cumulative ticks) and sensor_msgs/LaserScan (682 rays, frame
// "laser"), both stamped with the line's time.
#include <cstdio>
#include <iostream>

#include <rosbag/bag.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

#include "odometry_calibration/datasets/mines_log.h"

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  if (argc != 3 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cerr << "usage: mines_to_bag exp1.dat OUTPUT.bag\n";
    return argc == 2 ? 0 : 2;
  }
  const std::string output = argv[2];
  const std::string partial = output + ".partial";
  try {
    const std::vector<MinesRecord> records = loadMinesLog(argv[1]);
    if (records.empty())
      throw std::runtime_error(std::string(argv[1]) + " holds no line");
    rosbag::Bag bag(partial, rosbag::bagmode::Write);
    std::uint32_t seq = 0;
    for (const MinesRecord& record : records) {
      const ros::Time stamp(record.stamp_s);
      sensor_msgs::JointState joints;
      joints.header.seq = seq;
      joints.header.stamp = stamp;
      joints.name = {"left_wheel", "right_wheel"};
      joints.position = {record.left_ticks, record.right_ticks};
      bag.write("/joint_states", stamp, joints);
      const Scan core = minesScan(record);
      sensor_msgs::LaserScan scan;
      scan.header.seq = seq++;
      scan.header.stamp = stamp;
      scan.header.frame_id = "laser";
      scan.angle_min = static_cast<float>(core.angle_min_rad);
      scan.angle_increment = static_cast<float>(core.angle_increment_rad);
      scan.angle_max =
          static_cast<float>(core.angle_min_rad + core.angle_increment_rad * (kMinesRayCount - 1));
      scan.scan_time = 0.1f;
      scan.time_increment = static_cast<float>(kMinesTimePerRayS);  // for sweep compensation
      scan.range_min = static_cast<float>(core.range_min_m);
      scan.range_max = static_cast<float>(core.range_max_m);
      scan.ranges.assign(core.ranges_m.begin(), core.ranges_m.end());
      bag.write("/scan", stamp, scan);
    }
    bag.close();
    if (std::rename(partial.c_str(), output.c_str()) != 0) {
      throw std::runtime_error("cannot rename " + partial + " to " + output);
    }
    std::cout << "wrote " << records.size() << " JointState and LaserScan messages ("
              << records.back().stamp_s - records.front().stamp_s << " s) to " << output << "\n";
  } catch (const std::exception& error) {
    std::remove(partial.c_str());
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
