// Parsing of command-line values shared by the tools.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace odometry_calibration {

/// The whole of `text` as a finite number >= `minimum`; otherwise std::invalid_argument
/// "option <option>: expected a number [>= minimum], got '<text>'".
inline double parseNumberArgument(const std::string& option, const std::string& text,
                                  double minimum = -std::numeric_limits<double>::infinity())
{
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || errno != 0 || end != text.c_str() + text.size() || !std::isfinite(value) ||
      value < minimum) {
    char bound[48] = "";
    if (std::isfinite(minimum))
      std::snprintf(bound, sizeof(bound), " >= %g", minimum);
    throw std::invalid_argument("option " + option + ": expected a number" + bound + ", got '" +
                                text + "'");
  }
  return value;
}

}  // namespace odometry_calibration
