#include "odometry_calibration/common/histogram.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace odometry_calibration {

Histogram makeHistogram(const std::vector<double>& values, double upper, std::size_t bins)
{
  if (bins == 0)
    throw std::invalid_argument("a histogram needs at least one bin");
  if (!(upper > 0.0) || !std::isfinite(upper))
    throw std::invalid_argument("a histogram's upper limit must be a positive number");
  Histogram histogram;
  histogram.bin_width = upper / static_cast<double>(bins);
  histogram.counts.assign(bins, 0);
  for (const double value : values) {
    if (!(value < upper)) {  // NaN included: it belongs to no bin
      ++histogram.overflow;
      continue;
    }
    const double bin = std::floor(std::max(0.0, value) / histogram.bin_width);
    ++histogram.counts[std::min(bins - 1, static_cast<std::size_t>(bin))];
  }
  return histogram;
}

double histogramUpperLimit(const std::vector<std::vector<double>>& sets, double quantile,
                           double minimum)
{
  std::vector<double> all;
  for (const std::vector<double>& set : sets) {
    for (const double value : set) {
      if (std::isfinite(value))
        all.push_back(value);
    }
  }
  if (all.empty())
    return minimum;
  const double position = std::clamp(quantile, 0.0, 1.0) * static_cast<double>(all.size() - 1);
  const auto index = static_cast<std::ptrdiff_t>(std::ceil(position));
  std::nth_element(all.begin(), all.begin() + index, all.end());
  // Slightly above the quantile, so the value itself falls in the last bin, not the overflow.
  return std::max(minimum, all[static_cast<std::size_t>(index)] * 1.0001);
}

}  // namespace odometry_calibration
