// The joint fit of several ego-motion sources (`ego_motion.sources`, e.g. a front and
// a rear laser) from each source's own pairs and fit alone: one set of wheel parameters and one
// pose per sensor (models/joint_fits.h), the model a sensor's view of it gives, and the joint
// result.yaml. The one place calibrate_bag and the live node's session both fit sources jointly.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/joint_fit_report.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// One source's part of the joint fit: its pairs (cut at its own time offset) and its fit alone.
struct JointSourceInput
{
  std::string topic;  ///< the source's topic (the sensor's name in the tables)
  std::string frame;  ///< the sensor's frame (result.yaml's `sensors[].frame`)
  std::vector<MotionPair> pairs;
  Pose2 T_base_sensor_start;   ///< its pose fitted alone: the joint fit's start
  double time_offset_s = 0.0;  ///< its time offset (estimated or configured) [s]
  /// The keyframe interval of its pairs [s] (result.yaml's fit_interval_s; 0: not recorded).
  double fit_interval_s = 0.0;
};

/// Why `model` has no joint fit of several sources ("" when it has: diff_drive, skid_steer,
/// mecanum, tricycle).
std::string jointFitModelProblem(const std::string& model);

/// The joint fit of config.model from every source's pairs and start pose. Throws
/// std::invalid_argument naming the model (jointFitModelProblem) or the sensor whose pairs
/// cannot be fitted ("sensor <k> ('<topic>'): ...").
JointFitReport fitSourcesJointly(const CalibrationConfig& config,
                                 const std::vector<JointSourceInput>& sources);

/// The joint wheels with sensor `index`'s pose as a one-sensor model of config.model (its
/// prediction covariance zero, as a model from start values). Throws std::invalid_argument
/// when the joint fit's intrinsics are not config.model's.
std::shared_ptr<MotionModel> jointSensorModel(const CalibrationConfig& config,
                                              const JointFitReport& joint, std::size_t index);

/// result.yaml of the joint fit: the first sensor's view as the one-sensor result (so that a
/// one-source reader loads it: the joint wheels, the first sensor's pose, time offset and fit
/// interval), then `sensors`: every sensor's topic, frame, pose with σ, time offset, fit
/// interval (when recorded) and pair count. `source`:
/// result.yaml's `source` (the bag, the node).
std::string jointResultYaml(const CalibrationConfig& config, const JointFitReport& joint,
                            const std::vector<JointSourceInput>& sources,
                            const std::string& source);

}  // namespace odometry_calibration
