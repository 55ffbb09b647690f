// The names of the files and folders a calibration writes into its output directory.
#pragma once

namespace odometry_calibration {

inline constexpr const char* kPairsFileName = "pairs.csv";
inline constexpr const char* kResultFileName = "result.yaml";
inline constexpr const char* kControllerFileName = "controller.yaml";
inline constexpr const char* kLaserJointFileName = "laser_joint.urdf";         ///< one sensor
inline constexpr const char* kJointLaserJointsFileName = "laser_joints.urdf";  ///< several sensors
inline constexpr const char* kJointReportFileName = "joint_report.txt";        ///< several sensors
inline constexpr const char* kTextReportFileName = "report.txt";
inline constexpr const char* kReportFileName = "report.md";
inline constexpr const char* kPlotFolderName = "plots";
inline constexpr const char* kTrajectoryFolderName = "trajectories";  ///< TUM files

}  // namespace odometry_calibration
