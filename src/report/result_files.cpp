#include "odometry_calibration/report/result_files.h"

#include <filesystem>
#include <future>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/median.h"
#include "odometry_calibration/common/staged_file_set.h"
#include "odometry_calibration/report/controller_yaml.h"

namespace odometry_calibration {

const char* const kPairsFileName = "pairs.csv";
const char* const kResultFileName = "result.yaml";
const char* const kTextReportFileName = "report.txt";
const char* const kReportFileName = "report.md";
const char* const kPlotFolderName = "plots";
const char* const kControllerFileName = "controller.yaml";

ResultFiles resultFilesForJob(const JointLayout& joints, const CalibrationJobResult& job,
                              const std::string& source)
{
  ResultFiles files;
  files.pairs = {joints, job.pairs};
  std::vector<double> durations_s;
  for (const MotionPair& pair : job.pairs)
    durations_s.push_back(pair.end_stamp_s - pair.start_stamp_s);
  files.result_yaml = calibrationResultYaml(job.report, *job.model, source, job.time_offset_s,
                                            joints.names, median(durations_s));
  files.controller_yaml = controllerYaml(job.report, source);
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
  std::error_code error;
  std::filesystem::create_directories(output_dir, error);
  if (error || !std::filesystem::is_directory(output_dir)) {
    throw std::runtime_error("cannot create the output directory '" + output_dir +
                             "': " + (error ? error.message() : "a file has that name"));
  }
  // Every file staged beside its place first; the set replaces the old one only when all are
  // written (a full disk leaves the old set as it was, and no new file).
  StagedFileSet set(output_dir);
  const std::string plot_folder = set.stagedPath(kPlotFolderName);
  std::filesystem::create_directory(plot_folder);
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
      std::string("`") + kResultFileName + "`: the fitted model, parameters with σ, warnings",
      std::string("`") + kTextReportFileName + "`: what the terminal showed",
      std::string("`") + kPlotFolderName +
          "/`: the images, their data (`.dat`) and gnuplot scripts (`.gp`)"};
  std::vector<std::string> names = {kPairsFileName, kResultFileName, kTextReportFileName,
                                    kPlotFolderName, kReportFileName};
  std::vector<std::pair<std::string, std::string>> controller;
  std::vector<std::string> removed;
  addControllerFile(files.controller_yaml, &controller, &removed);
  for (const auto& [name, content] : controller) {
    markdown.files.push_back("`" + name +
                             "`: the fitted geometry as the robot's controller takes it, with σ");
    writeFileAtomically(set.stagedPath(name), content);
    names.push_back(name);
  }
  writeFileAtomically(set.stagedPath(kResultFileName), files.result_yaml);
  writeFileAtomically(set.stagedPath(kTextReportFileName), files.text_report);
  writeFileAtomically(set.stagedPath(kReportFileName), markdownReport(markdown));
  set.commit(names, removed);
  return plots;
}

}  // namespace odometry_calibration
