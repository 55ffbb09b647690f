// Fuzz target: the tricycle dataset (calibrate_tricycle's input), decoded into pairs as the
// tool does.
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream input(test::fuzzText(data, size));
  try {
    const TricycleDataset dataset = parseTricycleDataset(input, "dataset.txt");
    const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
    tricycleNominalFromHeader(dataset.header);
    const std::vector<EncoderSample> samples = decodeTricycleEncoders(dataset, layout);
    tricyclePairs(dataset, samples, 0.5, Eigen::Matrix3d::Identity() * 1e-4);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
