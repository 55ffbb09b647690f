#include "odometry_calibration/common/number_text.h"

#include <sstream>

namespace odometry_calibration {

std::string formatNumber(double value, int significant_digits)
{
  std::ostringstream stream;
  stream.precision(significant_digits);
  stream << value;
  return stream.str();
}

}  // namespace odometry_calibration
