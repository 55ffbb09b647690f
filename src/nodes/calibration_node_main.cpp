// odometry_calibration_node: the live calibration node (see README, "The live node").
#include <csignal>
#include <iostream>

#include <glog/logging.h>
#include <ros/ros.h>

#include "odometry_calibration/live_node/calibration_node.h"

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;  // Ceres' own progress lines
  // A file-size limit (ulimit -f) is a full disk for this node: a failed write, not a signal
  // that kills it (the pairs stay in memory until they can be written).
  std::signal(SIGXFSZ, SIG_IGN);
  ros::init(argc, argv, "odometry_calibration");
  // The handles outlive a failed start, so that the reason still reaches the log.
  ros::NodeHandle handle, private_handle("~");
  try {
    odometry_calibration::CalibrationNode node(handle, private_handle);
    ros::spin();
    // Stopped (SIGINT): pairs the disk never took are lost, and the exit status says so.
    if (const std::size_t lost = node.finish(); lost > 0) {
      std::cerr << "odometry_calibration_node: " << lost
                << " pairs lost (never written to the pairs file)" << std::endl;
      return 3;
    }
  } catch (const std::exception& error) {
    ROS_FATAL("cannot start: %s", error.what());
    std::cerr << "odometry_calibration_node: cannot start: " << error.what() << std::endl;
    return 1;
  }
  return 0;
}
