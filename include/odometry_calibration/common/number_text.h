// Numbers in messages for people: warnings, notes and errors that quote a measured value.
#pragma once

#include <string>

namespace odometry_calibration {

/// `value` with `significant_digits` significant digits in the shortest of fixed and scientific
/// notation, as printf's "%.<significant_digits>g" (e.g. 0.000123456 -> "0.000123", 1234.5 ->
/// "1.23e+03" at 3 digits); "inf", "-inf" and "nan" for those.
std::string formatNumber(double value, int significant_digits = 3);

}  // namespace odometry_calibration
