// calibrate_tricycle: fits the tricycle model to a log and prints the report.
#include <iostream>

#include <glog/logging.h>

#include "odometry_calibration/cli/tricycle_cli.h"

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  // Ceres logs through glog; the report already states everything a user must act on
  // (e.g. an unavailable covariance), so keep its internal messages off the terminal.
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  try {
    const TricycleCliOptions options =
        parseTricycleCliArguments(std::vector<std::string>(argv + 1, argv + argc));
    if (options.help) {
      std::cout << tricycleCliUsage();
      return 0;
    }
    return runTricycleCli(options, std::cout, std::cerr);
  } catch (const ArgumentError& error) {
    std::cerr << "error: " << error.what() << "\n\n" << tricycleCliUsage();
    return 2;
  }
}
