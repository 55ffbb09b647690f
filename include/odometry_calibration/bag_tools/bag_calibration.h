// calibrate_bag's job (README, "calibrate_bag"): the bags read once into the live node's own
// JointCalibrationSession (bag_runner.h), its fit (the node's ~calibrate: one source alone, or
// several sources each alone and then jointly), scores on test bags or a held-out part (one
// source), and the files of the run written together (report/result_files.h).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "odometry_calibration/common/gnuplot.h"
#include "odometry_calibration/session/joint_calibration_session.h"

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
/// status (calibrationExitStatus: 0, 3 not converged, 4 warnings, 5 the time offset; several
/// sources: of the joint fit, every sensor's warnings counted); throws std::exception for bad input
/// (unreadable bags or configuration, too few pairs). Several ego-motion sources
/// (`ego_motion.sources`, e.g. a front and a rear laser; models diff_drive, skid_steer, mecanum,
/// tricycle): each source's run and fit alone is printed, then the joint fit (a table per sensor
/// and the agreement of the fits alone); each source's files go to <output>/source_<k>/ and the
/// joint result.yaml, laser_joints.urdf, controller.yaml (not for tricycle) and joint_report.txt to
/// <output>, all as one set. When the joint fit (`fit_jointly`; a test forces a failure through it)
/// fails after every source was fitted alone, the sources' text is printed and their files written
/// (with joint_report.txt; an earlier run's joint result.yaml, laser_joints.urdf and
/// controller.yaml removed), then std::runtime_error says that the joint fit failed and why.
int calibrateBags(const BagCalibrationOptions& options, std::ostream& out,
                  const JointFitFunction& fit_jointly = fitSourcesJointly);

}  // namespace odometry_calibration
