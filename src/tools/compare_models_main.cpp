// compare_models: trains several models on some pairs files and scores them on others
// (the paper's Tables III/IV). The logic is in cli/compare_models_cli.h.
#include <iostream>
#include <string>
#include <vector>

#include "odometry_calibration/cli/compare_models_cli.h"

int main(int argc, char** argv)
{
  using namespace odometry_calibration;
  CompareModelsCliOptions options;
  try {
    options = parseCompareModelsCliArguments(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << compareModelsCliUsage();
    return 2;
  }
  if (options.help) {
    std::cout << compareModelsCliUsage();
    return 0;
  }
  return runCompareModelsCli(options, std::cout, std::cerr);
}
