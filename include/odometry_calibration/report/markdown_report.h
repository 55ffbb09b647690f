// The calibration report as a Markdown document with plots (calibrate_bag's report.md): what a
// user needs to trust a fit, on one page: the parameters with sigma, the observability
// verdict, the time offset and its cost curve, the per-pair errors before and after, the
// trajectories, how the pairs were collected and rejected.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/eval/trajectory_comparison.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/report/report_plots.h"

namespace odometry_calibration {

/// Everything the report shows.
struct MarkdownReportInput
{
  std::vector<std::string> bags;  ///< bag files calibrated on
  double data_span_s = 0.0;       ///< time covered by the data [s]
  double run_time_s = 0.0;        ///< wall time of reading and pairing [s]
  CollectorStatistics statistics;
  std::vector<std::string> collection_notes;  ///< skipped messages, restarts, in words
  ModelReport report;                         ///< the fit
  /// The time-offset search, when it ran.
  std::optional<TimeOffsetResult> time_offset;
  double time_offset_used_s = 0.0;  ///< the offset the final fit used [s]
  /// Chained trajectories and per-pair errors; `nominal_description` says what the nominal
  /// model is (empty: no nominal model).
  TrajectoryComparison trajectories;
  std::string nominal_description;
  std::string test_table;  ///< the comparison table on test bags (empty: none)
  std::size_t test_pairs = 0;
  std::string holdout_table;       ///< every model and the nominal on the held-out pairs (or empty)
  std::string holdout_note;        ///< which pairs were held out, in words
  std::string fit_interval_note;   ///< how the fit interval was chosen, in words (empty: fixed)
  ReportPlots plots;               ///< images made, or why not
  std::string plot_folder;         ///< folder of the images, relative to the report
  std::vector<std::string> files;  ///< the other files written, for the list at the end
};

/// The report text (GitHub-flavoured Markdown: tables, images).
std::string markdownReport(const MarkdownReportInput& input);

}  // namespace odometry_calibration
