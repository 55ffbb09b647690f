// The files of a bag calibration, written together at the end of a successful run: the pairs,
// the result YAML, the controller form, the text report, the plot folder and the Markdown
// report. All are staged beside their places and replace the previous set only when every one
// is written (common/staged_file_set.h), so a failed run (a full disk) leaves the old set as
// it was and no new file; a plot that cannot be drawn never fails the run.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/report/markdown_report.h"
#include "odometry_calibration/report/report_plots.h"

namespace odometry_calibration {

/// File and folder names inside the output directory.
extern const char* const kPairsFileName;       ///< "pairs.csv"
extern const char* const kResultFileName;      ///< "result.yaml"
extern const char* const kTextReportFileName;  ///< "report.txt"
extern const char* const kReportFileName;      ///< "report.md"
extern const char* const kPlotFolderName;      ///< "plots"
extern const char* const kControllerFileName;  ///< "controller.yaml"

/// What to write.
struct ResultFiles
{
  PairsFile pairs;
  std::string result_yaml;
  std::string controller_yaml;  ///< controller_yaml.h; empty: no controller form, no file
  std::string text_report;
  ReportPlotInput plots;         ///< data of the report's plots
  MarkdownReportInput markdown;  ///< the report (plots, plot_folder and files are filled in)
  GnuplotOptions gnuplot;        ///< the plotting program
};

/// The files of one calibration job: its pairs, result.yaml (calibrationResultYaml, naming
/// `source`), controller.yaml (controllerYaml, when the model has a controller form), the
/// plots' data and the report's fit, time offset and trajectories. The caller
/// adds what it knows of the collection (bags, statistics, notes), the text report, the test
/// table and the plotting program.
ResultFiles resultFilesForJob(const JointLayout& joints, const CalibrationJobResult& job,
                              const std::string& source);

/// Creates `output_dir` if needed and writes everything into it. Returns what happened to the
/// plots (their problem is empty when all were drawn). Throws std::runtime_error naming the
/// path when a file cannot be written (the previous set is then left whole, and no new file).
ReportPlots writeResultFiles(const std::string& output_dir, ResultFiles files);

}  // namespace odometry_calibration
