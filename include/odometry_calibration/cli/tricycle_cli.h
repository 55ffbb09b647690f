// The `calibrate_tricycle` command: options, parsing, and the run itself (kept out of main so
// tests can drive it).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// The automatic choice of the keyframe interval: the calibration session's (calibration/
/// fit_interval.h's time-blocked cross-validation with the criterion of a tracker's absolute
/// poses, the ATE), its evaluation pairs at the shortest candidate.
struct TricycleIntervalSelection
{
  /// Candidate keyframe intervals T [s], increasing.
  std::vector<double> candidates_s = {0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0};
  /// The fitted samples' evaluation pairs are cut into this many contiguous time blocks, once
  /// per entry (each in [2, 100]); a candidate's score is the mean ATE over all blocks of all
  /// cuts. Several cuts average out the luck of where one cut's block borders fall.
  std::vector<std::size_t> fold_counts = {2, 3, 4, 5, 6};
};

/// Everything the command can be told.
struct TricycleCliOptions
{
  std::string dataset_path;  ///< the log to calibrate (required)
  /// The result.yaml document (calibration_result.h, with the interval's choice and the scores);
  /// "" = do not write.
  std::string output_path = "tricycle_calibration.yaml";
  /// Keyframe spacing T [s]; 0 = chosen by time-blocked cross-validation (`--interval auto`).
  double keyframe_interval_s = 0.0;
  TricycleIntervalSelection interval_selection;  ///< candidates and folds of the automatic choice
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

/// Loads the log, fits, scores, prints the report to `out`, writes result.yaml. Returns the process
/// exit code: 0 success, 1 bad input (message on `err`), 3 the solver did not converge.
int runTricycleCli(const TricycleCliOptions& options, std::ostream& out, std::ostream& err);

}  // namespace odometry_calibration
