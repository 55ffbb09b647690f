// The `calibrate_tricycle` command: options, parsing, and the run itself (kept out of main so
// tests can drive it).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/eval/interval_selection.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// Everything the command can be told.
struct TricycleCliOptions
{
  std::string dataset_path;                               ///< the log to calibrate (required)
  std::string output_path = "tricycle_calibration.yaml";  ///< result YAML; "" = do not write
  /// Keyframe spacing T [s]; 0 = chosen by time-blocked cross-validation (`--interval auto`).
  double keyframe_interval_s = 0.0;
  IntervalSelectionOptions interval_selection;  ///< candidates and folds of the automatic choice
  /// Last fraction of the samples held out of the fit and used to score it (0: none).
  double holdout_fraction = 0.0;
  TricycleCalibrationOptions calibration;  ///< fit options
  bool help = false;                       ///< print usage and exit
};

/// Usage text with every option, its unit and default.
std::string tricycleCliUsage();

/// Parses argv-style arguments (without the program name) with ArgumentParser. Throws
/// ArgumentError naming the bad option or value.
TricycleCliOptions parseTricycleCliArguments(const std::vector<std::string>& arguments);

/// Loads the log, fits, prints the report to `out`, writes the YAML. Returns the process exit
/// code: 0 success, 1 bad input (message on `err`), 3 the solver did not converge.
int runTricycleCli(const TricycleCliOptions& options, std::ostream& out, std::ostream& err);

}  // namespace odometry_calibration
