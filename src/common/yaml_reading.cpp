#include "odometry_calibration/common/yaml_reading.h"

namespace odometry_calibration {

void rethrowWithYamlContext(const std::string& source, const std::string& where)
{
  try {
    throw;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(where + ": " + error.what());
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    throw std::runtime_error(message.rfind(source, 0) == 0 ? message : where + ": " + message);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(where + ": " + error.what());
  }
}

}  // namespace odometry_calibration
