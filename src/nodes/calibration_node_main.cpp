// odometry_calibration_node: the live calibration node (see README, "The live node").
#include <glog/logging.h>
#include <ros/ros.h>

#include "odometry_calibration/ros/calibration_node.h"

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;  // Ceres' own progress lines
  ros::init(argc, argv, "odometry_calibration");
  try {
    odometry_calibration::CalibrationNode node{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::exception& error) {
    ROS_FATAL("cannot start: %s", error.what());
    return 1;
  }
  return 0;
}
