// The plots of a calibration report, drawn by gnuplot as PNG: the scan-matched, nominal and
// calibrated trajectories, the histograms of the per-pair errors before and after the fit, and
// the time-offset cost curve. The data (.dat) and the gnuplot scripts (.gp) stay next to the
// images, so a plot can be redrawn or restyled by hand (`gnuplot trajectories.gp`).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/common/gnuplot.h"
#include "odometry_calibration/eval/trajectory_comparison.h"

namespace odometry_calibration {

/// File names of the images, inside the plot folder.
extern const char* const kTrajectoryPlot;   ///< "trajectories.png"
extern const char* const kResidualPlot;     ///< "residuals.png"
extern const char* const kTimeOffsetPlot;   ///< "time_offset.png"
extern const char* const kFitIntervalPlot;  ///< "fit_interval.png"

/// What to plot.
struct ReportPlotInput
{
  TrajectoryComparison trajectories;  ///< chained trajectories and per-pair errors
  std::string calibrated_label;       ///< legend of the calibrated model, e.g. "diff_drive"
  /// Time-offset cost curve (tau [s], cost [-]); empty: not estimated, no plot.
  std::vector<std::pair<double, double>> time_offset_curve;
  double time_offset_s = 0.0;        ///< the estimate, marked on the curve [s]
  double time_offset_sigma_s = 0.0;  ///< its sigma [s] (NaN: not determined)
  /// Validation curve of the fit interval (T [s], validation RPE or ATE [m];
  /// calibration/fit_interval.h);
  /// empty: not chosen by the data, no plot. Unscored candidates (infinite) are left out.
  std::vector<std::pair<double, double>> fit_interval_curve;
  double fit_interval_s = 0.0;                 ///< the chosen T, marked on the curve [s]
  double fit_interval_evaluation_s = 0.0;      ///< the evaluation pairs' interval [s]
  std::string fit_interval_criterion = "RPE";  ///< what the curve measures ("RPE" or "ATE")
};

/// What was drawn.
struct ReportPlots
{
  std::vector<std::string> images;  ///< file names made (valid PNG), in the order above
  /// Why images are missing, in words (empty when every image was made).
  std::string problem;
  bool has(const std::string& image) const;
};

/// Writes the data and scripts into `directory` (which must exist) and runs gnuplot there.
/// Never throws: a missing gnuplot, a failing script or an unwritable folder end up in
/// `problem`, and the images that were made are listed.
ReportPlots writeReportPlots(const ReportPlotInput& input, const std::string& directory,
                             const GnuplotOptions& gnuplot = GnuplotOptions());

/// Whether the file starts with the PNG signature and holds an IHDR chunk and an IEND chunk.
bool isPngFile(const std::string& path);

}  // namespace odometry_calibration
