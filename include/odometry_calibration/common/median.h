// The median of a sample, shared by the robust fits (MAD scales) and the reports.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace odometry_calibration {

/// Median of the values: the upper one of the two middle values of an even count; 0 for none.
inline double median(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace odometry_calibration
