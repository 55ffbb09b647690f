// compare_models' logic (the paper's Tables III/IV): trains several models on some pairs files and
// scores them on others; the main parses the arguments and calls runCompareModelsCli.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"

namespace odometry_calibration {

/// compare_models' options, as parsed from its arguments.
struct CompareModelsCliOptions
{
  std::vector<std::string> train;                                    ///< training pairs files
  std::vector<std::string> test;                                     ///< test pairs files
  std::vector<std::string> models = {"linear", "diff_drive", "gp"};  ///< models to compare
  std::string config_path;  ///< calibration config giving every model's options ("" = below)
  std::string left_joint, right_joint;  ///< diff_drive wheels ("" = the incremental joints)
  double ticks_per_rev = 2000.0;        ///< encoder ticks per wheel turn
  /// diff_drive start values: left and right radius, separation [m], sensor x, y [m], yaw [rad].
  std::vector<double> start = {0.077, 0.077, 0.33, 0.15, 0.0, 0.0};
  std::vector<std::string> wheel_joints;  ///< mecanum FL, FR, RL, RR ("" = incremental joints)
  /// mecanum start values: wheel radius, lx + ly [m], sensor x, y [m], yaw [rad].
  std::vector<double> mecanum_start = {0.05, 0.35, 0.15, 0.0, 0.0};
  bool help = false;  ///< print the usage and exit
};

/// The usage text of compare_models.
std::string compareModelsCliUsage();

/// The options of compare_models' arguments (without the program name). Throws ArgumentError
/// or std::invalid_argument on bad usage (unknown model, --config with the model options,
/// other than four wheel joints, no training or test file).
CompareModelsCliOptions parseCompareModelsCliArguments(const std::vector<std::string>& arguments);

/// Fits each model on the training pairs and prints the comparison table (and the models'
/// warnings) to `out`. Returns the exit status: 0 success, 1 bad input (message on `err`), 3 a
/// model's fit did not converge.
int runCompareModelsCli(const CompareModelsCliOptions& options, std::ostream& out,
                        std::ostream& err);

}  // namespace odometry_calibration
