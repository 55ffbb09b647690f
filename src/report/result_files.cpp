#include "odometry_calibration/report/result_files.h"

#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/median.h"
#include "odometry_calibration/common/staged_directory.h"

namespace odometry_calibration {

const char* const kPairsFileName = "pairs.csv";
const char* const kResultFileName = "result.yaml";
const char* const kTextReportFileName = "report.txt";
const char* const kReportFileName = "report.md";
const char* const kPlotFolderName = "plots";

ResultFiles resultFilesForJob(const JointLayout& joints, const CalibrationJobResult& job,
                              const std::string& source)
{
  ResultFiles files;
  files.pairs = {joints, job.pairs};
  std::vector<double> durations_s;
  for (const MotionPair& pair : job.pairs)
    durations_s.push_back(pair.end_stamp_s - pair.start_stamp_s);
  files.result_yaml =
      calibrationResultYaml(job.report, *job.model, source, job.time_offset_s, median(durations_s));
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
  // The plots first, in a folder that only appears on commit below.
  StagedDirectory plot_folder(output_dir, kPlotFolderName);
  const ReportPlots plots = writeReportPlots(files.plots, plot_folder.path(), files.gnuplot);

  MarkdownReportInput& markdown = files.markdown;
  markdown.plots = plots;
  markdown.plot_folder = kPlotFolderName;
  markdown.files = {
      std::string("`") + kPairsFileName + "`: the keyframe pairs (at the time offset used)",
      std::string("`") + kResultFileName + "`: the fitted model, parameters with σ, warnings",
      std::string("`") + kTextReportFileName + "`: what the terminal showed",
      std::string("`") + kPlotFolderName +
          "/`: the images, their data (`.dat`) and gnuplot scripts (`.gp`)"};
  const std::string report = markdownReport(markdown);

  writePairsCsv(output_dir + "/" + kPairsFileName, files.pairs);
  writeFileAtomically(output_dir + "/" + kResultFileName, files.result_yaml);
  writeFileAtomically(output_dir + "/" + kTextReportFileName, files.text_report);
  plot_folder.commit();
  writeFileAtomically(output_dir + "/" + kReportFileName, report);
  return plots;
}

}  // namespace odometry_calibration
