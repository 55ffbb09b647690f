// calibrate_bag with several ego-motion sources (issue 35: `ego_motion.sources`, e.g. a front and
// a rear laser): each source paired on its own against the same encoder track (its own run of
// the bags through a calibration session: its own consistency checks, scale check and time
// offset, paired again at its estimate when that is off), fitted alone, then one joint fit of
// the wheels and every source's pose (models/joint_fits.h).
#pragma once

#include <functional>
#include <ostream>
#include <vector>

#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/calibration/joint_source_fit.h"
#include "odometry_calibration/ros/bag_calibration.h"

namespace odometry_calibration {

/// The joint fit of the sources' pairs (fitSourcesJointly's signature).
using JointFitFunction =
    std::function<JointFitReport(const CalibrationConfig&, const std::vector<JointSourceInput>&)>;

/// The joint calibration of `config`'s sources from the options' bags: prints each source's run
/// and fit alone, then the joint fit (a table per sensor and the agreement of the fits alone),
/// writes each source's own files under <output>/source_<k>/ and the joint result.yaml (the
/// joint wheels, the first sensor's pose as the model's, and every sensor's pose under
/// `sensors`), laser_joints.urdf (one fixed joint per sensor, parent base_link), controller.yaml
/// (the joint wheels; not for tricycle) and joint_report.txt in <output>, all as one set.
/// Supports models diff_drive, skid_steer, mecanum and tricycle; throws std::runtime_error
/// naming the model otherwise, and what a source's run or fit alone throws (nothing written).
/// When the joint fit (`fit_jointly`, fitSourcesJointly but in a test) fails after every
/// source was fitted alone, the sources' text is printed and their files written (with
/// joint_report.txt; an earlier run's joint result.yaml, laser_joints.urdf and controller.yaml
/// removed), then std::runtime_error says that the joint fit failed and why. Returns the exit
/// status (calibrationExitStatus of the joint fit, every sensor's warnings counted).
int calibrateBagsJointly(const BagCalibrationOptions& options, CalibrationConfig config,
                         std::ostream& out,
                         const JointFitFunction& fit_jointly = fitSourcesJointly);

}  // namespace odometry_calibration
