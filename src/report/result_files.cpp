#include "odometry_calibration/report/result_files.h"

#include <filesystem>
#include <future>
#include <stdexcept>

#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/staged_file_set.h"

namespace odometry_calibration {

namespace {

namespace fs = std::filesystem;

/// What a calibration file is, for the report's list of files.
std::string describeFile(const std::string& name)
{
  if (name == kResultFileName)
    return "the fitted model, parameters with σ, warnings";
  if (name == kControllerFileName)
    return "the fitted geometry as the robot's controller takes it, with σ";
  if (name == kLaserJointFileName)
    return "the sensor's pose as a fixed URDF joint (x, y, yaw)";
  return "";
}

void createDirectory(const std::string& directory)
{
  std::error_code error;
  fs::create_directories(directory, error);
  if (error || !fs::is_directory(directory)) {
    throw std::runtime_error("cannot create the output directory '" + directory +
                             "': " + (error ? error.message() : "a file has that name"));
  }
}

/// Stages the TUM trajectories (folder kTrajectoryFolderName, replaced whole; an earlier run's
/// removed when this one has none).
void stageTrajectories(StagedFileSet& set,
                       const std::vector<std::pair<std::string, std::string>>& trajectories,
                       std::vector<std::string>* names, std::vector<std::string>* removed)
{
  if (trajectories.empty()) {
    removed->push_back(kTrajectoryFolderName);
    return;
  }
  const fs::path folder = set.stagedPath(kTrajectoryFolderName);
  for (const auto& [name, content] : trajectories) {
    const fs::path path = folder / name;
    fs::create_directories(path.parent_path());
    writeFileAtomically(path.string(), content);
  }
  names->push_back(kTrajectoryFolderName);
}

/// Stages `files` into `set`: the entries to move in are appended to `names`, those to remove
/// to `removed`. Returns what happened to the plots.
ReportPlots stageResultFiles(StagedFileSet& set, ResultFiles files, std::vector<std::string>* names,
                             std::vector<std::string>* removed)
{
  const std::string plot_folder = set.stagedPath(kPlotFolderName);
  fs::create_directory(plot_folder);
  // pairs.csv, the largest file, is written while gnuplot draws (it waits for the plots; on
  // this thread at get() when no thread can be made).
  std::future<void> pairs_csv = std::async(std::launch::async | std::launch::deferred, [&] {
    writePairsCsv(set.stagedPath(kPairsFileName), files.pairs);
  });
  const ReportPlots plots = writeReportPlots(files.plots, plot_folder, files.gnuplot);
  pairs_csv.get();

  MarkdownReportInput& markdown = files.markdown;
  markdown.plots = plots;
  markdown.plot_folder = kPlotFolderName;
  markdown.files = {
      std::string("`") + kPairsFileName + "`: the keyframe pairs (at the time offset used)",
      std::string("`") + kTextReportFileName + "`: what the terminal showed",
      std::string("`") + kPlotFolderName +
          "/`: the images, their data (`.dat`) and gnuplot scripts (`.gp`)"};
  for (const char* name : {kPairsFileName, kTextReportFileName, kPlotFolderName})
    names->push_back(name);
  std::size_t listed = 1;  // after pairs.csv
  for (const auto& [name, content] : files.calibration.written) {
    markdown.files.insert(markdown.files.begin() + listed++,
                          "`" + name + "`: " + describeFile(name));
    writeFileAtomically(set.stagedPath(name), content);
    names->push_back(name);
  }
  for (const std::string& name : files.calibration.removed)
    removed->push_back(name);
  stageTrajectories(set, files.trajectories, names, removed);
  if (!files.trajectories.empty()) {
    markdown.files.push_back(std::string("`") + kTrajectoryFolderName +
                             "/`: each scored model's dead reckoning and the scan matches in TUM "
                             "format (`evo_ape tum`)");
  }
  writeFileAtomically(set.stagedPath(kTextReportFileName), files.text_report);
  writeFileAtomically(set.stagedPath(kReportFileName), markdownReport(markdown));
  names->push_back(kReportFileName);
  return plots;
}

}  // namespace

ResultFiles resultFilesForJob(const JointLayout& joints, const CalibrationJobResult& job,
                              double fit_interval_s, const std::string& source,
                              const std::string& sensor_frame)
{
  ResultFiles files;
  files.pairs = {joints, job.pairs};
  CalibrationFilesInput calibration;
  calibration.report = &job.report;
  calibration.model = job.model.get();
  calibration.source = source;
  calibration.time_offset_s = job.time_offset_s;
  calibration.joints = joints.names;
  calibration.fit_interval_s = fit_interval_s;
  if (job.report.has_extrinsic)
    calibration.T_base_sensor = job.report.T_base_sensor;
  calibration.sensor_frame = sensor_frame;
  files.calibration = calibrationFiles(calibration);
  files.plots.trajectories = job.trajectories;
  files.plots.calibrated_label = job.report.model;
  if (job.time_offset) {
    files.plots.time_offset_curve = job.time_offset->curve;
    files.plots.time_offset_s = job.time_offset->offset_s;
    files.plots.time_offset_sigma_s = job.time_offset->sigma_s;
  }
  files.markdown.report = job.report;
  files.markdown.time_offset = job.time_offset;
  files.markdown.time_offset_used_s = job.time_offset_s;
  files.markdown.trajectories = job.trajectories;
  files.markdown.nominal_description = job.nominal_description;
  return files;
}

ReportPlots writeResultFiles(const std::string& output_dir, ResultFiles files)
{
  createDirectory(output_dir);
  // Every file staged beside its place first; the set replaces the old one only when all are
  // written (a full disk leaves the old set as it was, and no new file).
  StagedFileSet set(output_dir);
  std::vector<std::string> names, removed;
  const ReportPlots plots = stageResultFiles(set, std::move(files), &names, &removed);
  set.commit(names, removed);
  return plots;
}

std::vector<std::string> writeJointResultFiles(const std::string& output_dir, const FileSet& joint,
                                               std::vector<ResultFiles> sources)
{
  createDirectory(output_dir);
  StagedFileSet set(output_dir);
  std::vector<std::string> names;
  for (const auto& [name, content] : joint.written) {
    writeFileAtomically(set.stagedPath(name), content);
    names.push_back(name);
  }
  for (std::size_t k = 0; k < sources.size(); ++k) {  // each folder one entry: replaced whole
    names.push_back("source_" + std::to_string(k));
    writeResultFiles(set.stagedPath(names.back()), std::move(sources[k]));
  }
  set.commit(names, joint.removed);
  return names;
}

}  // namespace odometry_calibration
