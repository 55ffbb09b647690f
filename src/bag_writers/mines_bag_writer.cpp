#include "odometry_calibration/bag_writers/mines_bag_writer.h"

#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include <rosbag/bag.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

namespace odometry_calibration {
namespace {

void writeRecords(const std::vector<MinesRecord>& records, const std::string& path)
{
  rosbag::Bag bag(path, rosbag::bagmode::Write);
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
}

}  // namespace

void writeMinesBag(const std::vector<MinesRecord>& records, const std::string& bag_path)
{
  if (records.empty())
    throw std::runtime_error("no Mines record to write to " + bag_path);
  const std::string partial = bag_path + ".partial";
  try {
    writeRecords(records, partial);
    if (std::rename(partial.c_str(), bag_path.c_str()) != 0) {
      throw std::runtime_error("cannot rename " + partial + " to " + bag_path);
    }
  } catch (...) {
    std::remove(partial.c_str());
    throw;
  }
}

}  // namespace odometry_calibration
