// The joint fits of the parametric models (issue 35: diff_drive, mecanum): one set of wheel
// parameters and one pose per sensor from each sensor's pairs (joint_parametric_fit.h).
#pragma once

#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/joint_fit_report.h"
#include "odometry_calibration/models/mecanum_model.h"

namespace odometry_calibration {

/// The differential drive's radii and separation, and the pose of each sensor, from
/// `pairs_per_sensor` (one set per sensor, each at least the 6 pairs a fit alone needs, with
/// both wheel joints). `start_poses`: each sensor's start pose (one per set; the options' own
/// initial_T_base_sensor is not used); the intrinsics start at the options' values. Throws
/// std::invalid_argument naming the sensor whose pairs cannot be fitted.
JointFitReport fitJointDiffDrive(const DiffDriveOptions& options,
                                 const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                 const std::vector<Pose2>& start_poses);

/// The mecanum base's four radii and lx + ly, and the pose of each sensor, as
/// fitJointDiffDrive (each set at least the 9 pairs a fit alone needs, with the four wheel
/// joints); each sensor's warnings also name the motions its own pairs lack
/// (mecanumMotionWarnings).
JointFitReport fitJointMecanum(const MecanumOptions& options,
                               const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                               const std::vector<Pose2>& start_poses);

}  // namespace odometry_calibration
