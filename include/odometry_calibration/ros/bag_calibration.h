// calibrate_bag's job (README, "calibrate_bag"): the bags fed to a calibration session
// (bag_runner.h; paired again at the estimated time offset when it is off), the session's fit
// (the same code as the live node's ~calibrate), scores on test bags or a held-out part, and the
// files of the run written together (report/result_files.h).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/gnuplot.h"

namespace odometry_calibration {

struct BagCalibrationOptions
{
  std::string config_path;             ///< --config
  std::vector<std::string> bags;       ///< the bags to calibrate from
  std::string output_dir;              ///< --output-dir (empty: the config's output_directory)
  std::string model;                   ///< --model (empty: the config's)
  std::vector<std::string> test_bags;  ///< --test
  double start_s = 0.0, end_s = 0.0;   ///< --start, --end [s after the first message]
  double holdout = 0.0;                ///< --holdout: the last fraction held out (0: none)
  std::string interval;                ///< --interval: "", "auto" or seconds
  bool quiet = false;                  ///< no progress display
  bool single_thread = false;          ///< no matching thread
  bool print_config = false;           ///< print the effective configuration, read no bag
  GnuplotOptions gnuplot;              ///< --gnuplot
};

/// Checks the options' values. Throws std::invalid_argument naming the bad one.
void checkBagCalibrationOptions(const BagCalibrationOptions& options);

/// Runs the calibration, prints what it did to `out` and writes the files. Returns the exit
/// status (calibrationExitStatus: 0, 3 not converged, 4 warnings); throws std::exception for bad
/// input (unreadable bags or configuration, too few pairs).
int calibrateBags(const BagCalibrationOptions& options, std::ostream& out);

}  // namespace odometry_calibration
