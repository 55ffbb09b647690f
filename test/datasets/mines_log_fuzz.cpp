// Fuzz target: the Mines rover log (mines_to_bag's input) and its scans.
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/datasets/mines_log.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream input(test::fuzzText(data, size));
  try {
    for (const MinesRecord& record : parseMinesLog(input, "exp1.dat"))
      minesScan(record);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
