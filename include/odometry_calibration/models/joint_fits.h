// The joint fits of the parametric models (diff_drive, skid_steer, mecanum,
// tricycle): one set of wheel parameters and one pose per sensor from each sensor's pairs
// (joint_parametric_fit.h).
#pragma once

#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/joint_fit_report.h"
#include "odometry_calibration/models/mecanum_model.h"
#include "odometry_calibration/models/skid_steer_model.h"
#include "odometry_calibration/models/tricycle_model.h"

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

/// The skid-steer base's effective radii and separation (its sides averaged into two virtual
/// wheels, skid_steer_model.h, then fitJointDiffDrive's solve), and the pose of each sensor
/// (each set at least 6 pairs with every wheel joint of both sides). The intrinsics start at
/// the geometric values; `derived` (and each fit alone's rows) holds the multipliers of the
/// geometric values a diff_drive_controller takes. Throws std::invalid_argument naming the
/// sensor whose pairs cannot be fitted.
JointFitReport fitJointSkidSteer(const SkidSteerOptions& options,
                                 const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                 const std::vector<Pose2>& start_poses);

/// The tricycle's Ks, Kt, axis length and steering offset (docs/models.md, "The tricycle"),
/// and the pose of each sensor: each set (at least the 7 pairs a fit alone needs, with the
/// steering and traction joints) first fitted alone as TricycleModel::fit does (from the
/// options' start values and its own `start_poses` entry, the physical of the symmetric
/// solutions kept), then solved jointly from the mean of those (solveJointParametricModel).
/// Throws std::invalid_argument naming the sensor whose pairs cannot be fitted.
JointFitReport fitJointTricycle(const TricycleModelOptions& options,
                                const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                                const std::vector<Pose2>& start_poses);

}  // namespace odometry_calibration
