// Fuzz target: the pairs file (resumed by the node, read by compare_models).
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/data/pairs_csv.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream input(test::fuzzText(data, size));
  try {
    const PairsFile file = parsePairsCsv(input, "pairs.csv");
    for (const MotionPair& pair : file.pairs)
      pairsCsvRow(pair);
    pairsCsvHeader(file.joints);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
