// calibrate_bag: reads bags directly (no playback), feeds them to the same calibration session
// as the live node, fits the configured model, and writes the pairs, the result and a report
// (ros/bag_calibration.h).
#include <unistd.h>

#include <iostream>

#include <glog/logging.h>

#include "odometry_calibration/bag/bag_message_reader.h"
#include "odometry_calibration/bag_tools/bag_calibration.h"
#include "odometry_calibration/common/arguments.h"

namespace {

const char* kUsage =
    "usage: calibrate_bag --config CONFIG.yaml BAG [BAG ...] [options]\n"
    "\n"
    "Reads the bags in timestamp order (ROS 1 .bag files with the rosbag API, or rosbag2\n"
    "recordings in SQLite storage: a bag folder with metadata.yaml, a .db3 or .db3.zstd),\n"
    "makes keyframe pairs (PLICP scan matching, or the configured ego-motion topic), fits\n"
    "the configured model and writes pairs.csv, result.yaml, report.txt and report.md (the\n"
    "report with plots in plots/, drawn by gnuplot) to the output directory, and for\n"
    "diff_drive, skid_steer and mecanum fits controller.yaml (the geometry as the robot's\n"
    "controller takes it).\n"
    "\n"
    "options:\n"
    "  --output-dir DIR     where to write (default: the config's output_directory)\n"
    "  --model NAME         fit this model instead of the config's (diff_drive, tricycle,\n"
    "                       mecanum, skid_steer, linear, gp)\n"
    "  --test BAG           score the models on this bag too (repeatable); prints the paper's\n"
    "                       comparison table for the model, the config's compare_models and\n"
    "                       the nominal robot (prior_model's start values, not fitted)\n"
    "  --start S, --end S   use only [S, E] seconds after the first message\n"
    "  --holdout F          hold out the pairs of the last fraction F (0 < F < 1) of the\n"
    "                       collection: fit on the others, score calibrated and nominal\n"
    "                       models on them\n"
    "  --interval T|auto    keyframe interval of the fitted pairs [s] (default: the config's\n"
    "                       keyframes.interval_s); auto: chosen among keyframes.\n"
    "                       fit_intervals_s (the default when set; else 0.3, 0.5, 1.0 s) by\n"
    "                       time-blocked cross-validation (the bags are paired once per\n"
    "                       interval); held-out and validation scores always use pairs at\n"
    "                       keyframes.interval_s\n"
    "  --quiet              no progress display\n"
    "  --print-config       print the effective configuration (every key, commented with its\n"
    "                       unit, range and default; with --model, as that model needs it)\n"
    "                       and exit 0; no bag needed\n"
    "  --single-thread      no matching thread: every match in the pairing thread (same\n"
    "                       results, slower)\n"
    "  --gnuplot PROGRAM    the plotting program (default: gnuplot from PATH; without it the\n"
    "                       report is written without images and says what is missing)\n"
    "\n"
    "exit status: 0 a result to stand behind (advice may be printed); 1 bad input or a\n"
    "configured value the data contradicts (the message names the file or key and the value\n"
    "to set); 2 bad usage; 3 the fit did not converge; 4 a parameter is not determined; 5 the\n"
    "time offset sits at the edge of its search range or is not observable\n";

}  // namespace

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  // A corrupted bag index makes rosbag read outside its buffers: exit 1 naming the bag.
  odometry_calibration::containBagReadFaults();
  FLAGS_minloglevel = google::GLOG_FATAL;
  odometry_calibration::BagCalibrationOptions o;
  o.quiet = !isatty(STDERR_FILENO);
  try {
    odometry_calibration::ArgumentParser parser;
    parser.option("--config", &o.config_path)
        .option("--output-dir", &o.output_dir)
        .option("--model", &o.model)
        .option("--gnuplot", &o.gnuplot.program)
        .repeatedOption("--test", &o.test_bags)
        .number("--start", &o.start_s, 0.0)
        .number("--end", &o.end_s, 0.0)
        .number("--holdout", &o.holdout, 0.0)
        .option("--interval", &o.interval)
        .flag("--quiet", &o.quiet)
        .flag("--single-thread", &o.single_thread)
        .flag("--print-config", &o.print_config)
        .positionals(&o.bags);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    odometry_calibration::checkBagCalibrationOptions(o);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    return odometry_calibration::calibrateBags(o, std::cout);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
