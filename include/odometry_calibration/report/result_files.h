// The files of a bag calibration, written together at the end of a successful run: the pairs,
// the calibration's files (calibration_files.h: result.yaml, controller.yaml, laser_joint.urdf),
// the text report, the plot folder and the Markdown report; with several sensors each sensor's
// set in source_<k>/ beside the joint fit's files. All are staged beside their places and replace
// the previous set only when every one is written (common/staged_file_set.h), so a failed run (a
// full disk) leaves the old set as it was and no new file; a plot that cannot be drawn never fails
// the run.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/report/calibration_files.h"
#include "odometry_calibration/report/markdown_report.h"
#include "odometry_calibration/report/report_plots.h"

namespace odometry_calibration {

/// What to write.
struct ResultFiles
{
  PairsFile pairs;
  FileSet calibration;  ///< the calibration's files (calibrationFiles)
  std::string text_report;
  ReportPlotInput plots;         ///< data of the report's plots
  MarkdownReportInput markdown;  ///< the report (plots, plot_folder and files are filled in)
  GnuplotOptions gnuplot;        ///< the plotting program
  /// The scored models' trajectories in TUM format (eval/tum_trajectory.h): path under
  /// `trajectories/` ("holdout/gp.sensor.tum") and content; none: no `trajectories/` folder.
  std::vector<std::pair<std::string, std::string>> trajectories;
};

/// The files of one calibration job fitted at `fit_interval_s` [s]: its pairs, its calibration
/// files (calibrationFiles: result.yaml naming `source`, controller.yaml, laser_joint.urdf in
/// `sensor_frame` when the fit estimated the sensor's pose), the plots' data and the report's
/// fit, time offset and trajectories. The caller adds what it knows of the collection (bags,
/// statistics, notes), the text report, the test table and the plotting program.
ResultFiles resultFilesForJob(const JointLayout& joints, const CalibrationJobResult& job,
                              double fit_interval_s, const std::string& source,
                              const std::string& sensor_frame);

/// Creates `output_dir` if needed and writes everything into it. Returns what happened to the
/// plots (their problem is empty when all were drawn). Throws std::runtime_error naming the
/// path when a file cannot be written (the previous set is then left whole, and no new file).
ReportPlots writeResultFiles(const std::string& output_dir, ResultFiles files);

/// Several sensors: `joint` (jointCalibrationFiles, or failedJointCalibrationFiles) in
/// `output_dir` and sensor k's `sources[k]` in `output_dir`/source_<k>/, all as one set as
/// writeResultFiles writes one. Returns the names written at the top ("source_<k>" for the
/// folders).
std::vector<std::string> writeJointResultFiles(const std::string& output_dir, const FileSet& joint,
                                               std::vector<ResultFiles> sources);

}  // namespace odometry_calibration
