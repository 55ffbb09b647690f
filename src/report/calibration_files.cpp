#include "odometry_calibration/report/calibration_files.h"

#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/staged_file_set.h"
#include "odometry_calibration/report/controller_yaml.h"

namespace odometry_calibration {

namespace {

namespace fs = std::filesystem;

/// controller.yaml with `controller` (controllerYaml's text), or its removal when it is empty.
void addControllerFile(const std::string& controller, FileSet* set)
{
  if (!controller.empty())
    set->written.emplace_back(kControllerFileName, controller);
  else
    set->removed.push_back(kControllerFileName);
}

}  // namespace

void FileSet::addUnder(const std::string& folder, const FileSet& other)
{
  for (const auto& [name, text] : other.written)
    written.emplace_back(folder + "/" + name, text);
  for (const std::string& name : other.removed)
    removed.push_back(folder + "/" + name);
}

std::string FileSet::content(const std::string& name) const
{
  for (const auto& [file, text] : written) {
    if (file == name)
      return text;
  }
  return "";
}

FileSet calibrationFiles(const CalibrationFilesInput& input)
{
  if (!input.report || !input.model)
    throw std::invalid_argument("calibrationFiles: a fit needs its report and its model");
  FileSet set;
  set.written.emplace_back(
      kResultFileName,
      calibrationResultYaml(*input.report, *input.model, input.source, input.time_offset_s,
                            input.joints, input.fit_interval_s));
  addControllerFile(controllerYaml(*input.report, input.source), &set);
  if (input.T_base_sensor) {
    set.written.emplace_back(
        kLaserJointFileName,
        laserJointUrdf(*input.T_base_sensor, input.base_frame, input.sensor_frame));
  } else {  // an earlier calibration's pose must not pass for this one's
    set.removed.push_back(kLaserJointFileName);
  }
  return set;
}

FileSet jointCalibrationFiles(const CalibrationConfig& config, const JointFitReport& joint,
                              const std::vector<JointSourceInput>& sources,
                              const std::string& source, const std::string& base_frame,
                              const std::string& report_text)
{
  FileSet set;
  set.written.emplace_back(kResultFileName, jointResultYaml(config, joint, sources, source));
  std::string urdf;
  for (std::size_t s = 0; s < joint.sensors.size() && s < sources.size(); ++s)
    urdf += laserJointUrdf(joint.sensors[s].T_base_sensor, base_frame, sources[s].frame);
  set.written.emplace_back(kJointLaserJointsFileName, urdf);
  addControllerFile(jointControllerYaml(joint, source), &set);
  set.written.emplace_back(kJointReportFileName, report_text);
  return set;
}

FileSet failedJointCalibrationFiles(const std::string& report_text)
{
  FileSet set;
  set.written.emplace_back(kJointReportFileName, report_text);
  set.removed = {kResultFileName, kJointLaserJointsFileName, kControllerFileName};
  return set;
}

void writeFileSet(const std::string& directory, const FileSet& set)
{
  std::error_code error;
  fs::create_directories(directory, error);
  if (error || !fs::is_directory(directory)) {
    throw std::runtime_error("cannot create the output directory '" + directory +
                             "': " + (error ? error.message() : "a file has that name"));
  }
  StagedFileSet staged(directory);
  std::vector<std::string> names;
  for (const auto& [name, content] : set.written) {
    if (const fs::path folder = fs::path(name).parent_path(); !folder.empty())
      fs::create_directories(fs::path(directory) / folder);  // must exist at the commit
    try {
      writeFileAtomically(staged.stagedPath(name), content);
    } catch (const std::exception& write_error) {
      throw std::runtime_error("cannot write " + name + ": " + write_error.what());
    }
    names.push_back(name);
  }
  staged.commit(names, set.removed);
}

void appendToResult(FileSet* files, const std::string& block)
{
  for (auto& [name, content] : files->written) {
    if (name == kResultFileName)
      content += block;
  }
}

void appendGyroResult(FileSet* files, const GyroFit& gyro, const std::string& topic)
{
  appendToResult(files, gyroResultYaml(gyro, topic));
}

}  // namespace odometry_calibration
