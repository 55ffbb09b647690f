// Fuzz target: a tricycle log through calibrate_tricycle's whole run (issue 32: the reader alone
// never reached the fit, where a tracker x of 1e308 crashed the covariance): the log read, the
// pairs cut at 0.5 s, the fit, the ATE and the report; nothing written.
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "odometry_calibration/cli/tricycle_cli.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  TricycleCliOptions options;
  options.dataset_path = test::fuzzFile(test::fuzzText(data, size), "_tricycle.txt");
  options.output_path.clear();
  options.keyframe_interval_s = 0.5;  // the automatic choice fits ten times: too slow here
  std::ostringstream out, err;
  runTricycleCli(options, out, err);  // exit codes and messages are the run's; a crash is not
  std::remove(options.dataset_path.c_str());
  return 0;
}
