// The files that say what a calibration found, made in one place for the live node's ~save and
// calibrate_bag alike: one sensor's result.yaml, controller.yaml and laser_joint.urdf; a joint
// fit's result.yaml, laser_joints.urdf, controller.yaml and joint_report.txt; and the writing of
// such a set into a directory as one (common/staged_file_set.h: all replaced, or none).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/calibration/joint_source_fit.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/report/output_file_names.h"

namespace odometry_calibration {

/// Files to write into one directory as one set: (name, content) in writing order, and the
/// names of an earlier set's files this one has not (removed when it is written). A name may
/// lie in a subfolder ("source_0/result.yaml").
struct FileSet
{
  std::vector<std::pair<std::string, std::string>> written;
  std::vector<std::string> removed;

  /// Adds `other`'s files and removals under `folder`/.
  void addUnder(const std::string& folder, const FileSet& other);
  /// The content of the file `name` (empty when the set does not write it).
  std::string content(const std::string& name) const;
};

/// One sensor's fitted calibration, as its files need it.
struct CalibrationFilesInput
{
  const ModelReport* report = nullptr;  ///< the fit's report (required)
  const MotionModel* model = nullptr;   ///< the fitted model (required)
  std::string source;                   ///< result.yaml's `source`: the bag, the node
  double time_offset_s = 0.0;           ///< encoder values at scan time + offset [s]
  std::vector<std::string> joints;      ///< the model's joints, in its order
  double fit_interval_s = 0.0;          ///< the keyframe interval the fit used [s]
  /// The sensor's pose on the robot (the fit's, or one known before); none: no URDF.
  std::optional<Pose2> T_base_sensor;
  std::string base_frame = "base_link";  ///< the URDF joint's parent
  std::string sensor_frame = "laser";    ///< the URDF joint's child
};

/// result.yaml (calibrationResultYaml, `fit_interval_s` the interval the fit used), then
/// controller.yaml (controllerYaml; removed instead when the model has no controller form, so
/// that an earlier calibration's values do not pass for this one's), then laser_joint.urdf
/// when a sensor pose is known (removed likewise when none is). Throws std::invalid_argument
/// without a report or model.
FileSet calibrationFiles(const CalibrationFilesInput& input);

/// `files`' result.yaml with `block` (a YAML block of top-level keys: gyroResultYaml,
/// fitIntervalChoiceYaml, scoresYaml) appended.
void appendToResult(FileSet* files, const std::string& block);

/// `files`' result.yaml with the gyro's block (gyroResultYaml of `gyro` on `topic`) appended.
void appendGyroResult(FileSet* files, const GyroFit& gyro, const std::string& topic);

/// A joint fit of several sensors: result.yaml (jointResultYaml), laser_joints.urdf (one fixed
/// joint per sensor, parent `base_frame`, child the sensor's frame), controller.yaml (the joint
/// wheels; removed when the model has none) and joint_report.txt (`report_text`). Throws what
/// the model's YAML throws for values a diverged solve left (a failed joint fit).
FileSet jointCalibrationFiles(const CalibrationConfig& config, const JointFitReport& joint,
                              const std::vector<JointSourceInput>& sources,
                              const std::string& source, const std::string& base_frame,
                              const std::string& report_text);

/// A joint fit that failed after every sensor was fitted alone: joint_report.txt
/// (`report_text`), and an earlier run's joint result.yaml, laser_joints.urdf and
/// controller.yaml removed, so that none passes for this run's.
FileSet failedJointCalibrationFiles(const std::string& report_text);

/// Writes `set` into `directory` (created if needed, subfolders too) as one: every file staged
/// beside its place, then all moved in and the removed ones removed; when one cannot be
/// written, std::runtime_error names it and the previous set stays whole.
void writeFileSet(const std::string& directory, const FileSet& set);

}  // namespace odometry_calibration
