// Fuzz target: result.yaml (loaded by the node on start), and a prediction with its model.
#include <cstdint>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "support/fuzz_input.h"

using namespace odometry_calibration;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  try {
    const CalibrationResult result =
        parseCalibrationResult(test::fuzzText(data, size), "result.yaml");
    if (result.model) {
      result.model->toYaml();
      for (const int joints : {1, 2, 3}) {
        try {
          result.model->predict({{0.0, Eigen::VectorXd::Zero(joints)},
                                 {0.25, Eigen::VectorXd::Constant(joints, 10.0)},
                                 {0.5, Eigen::VectorXd::Constant(joints, 25.0)}});
        } catch (const std::invalid_argument&) {
        } catch (const std::runtime_error&) {
        }
      }
    }
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  } catch (const YAML::Exception&) {
  }
  return 0;
}
